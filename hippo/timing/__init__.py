"""hippo.timing."""
