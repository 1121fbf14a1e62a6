"""hippo.sim."""
