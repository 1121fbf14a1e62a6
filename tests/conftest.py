import os

# one BLAS thread: on a shared 2-core machine multi-threaded BLAS stalls (a 0.35 s fit took 59 s)
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import matplotlib

matplotlib.use("Agg")
os.environ.setdefault("HIPPO_QUIET", "1")
