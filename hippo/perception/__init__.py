"""hippo.perception."""
