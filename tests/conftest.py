import os

import matplotlib

matplotlib.use("Agg")
os.environ.setdefault("HIPPO_QUIET", "1")
