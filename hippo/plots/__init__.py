"""hippo.plots."""
