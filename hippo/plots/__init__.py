"""Figures (matplotlib, Agg backend): ``hippo.plots.sim``, ``.perception``, ``.timing``,
``.cognitive_map``, ``.agent``."""

import matplotlib

if matplotlib.get_backend().lower() not in ("agg", "pdf", "svg", "ps", "cairo"):
    matplotlib.use("Agg")
