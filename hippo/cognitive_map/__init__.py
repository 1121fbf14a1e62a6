"""hippo.cognitive_map."""
