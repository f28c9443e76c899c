"""Numpy's BLAS on the calling thread, for the commands that run the simulated pick loop.

The pick loop's matrix products are thin: many points times a 3 x 3 frame or a few axes.
For such a product, waking OpenBLAS's thread pool costs more CPU than the product itself, and
many times more when the cores are busy (a 2-core machine with a benchmark beside it: a
projection of 16 ms on the pool, 0.1 ms on the calling thread). The benchmarks' worker
processes already run on one thread (:data:`~grasp_pipeline.bench.jobs.SINGLE_THREAD_ENV`);
this gives ``run``, ``demo``, ``record`` and ``eval`` the same. It takes effect only before
numpy is first imported, and a value the user set is kept (``OPENBLAS_NUM_THREADS=4
grasp-pipeline run ...`` still uses four threads).
"""

from __future__ import annotations

import os
import sys

#: The variable numpy's and scipy's bundled OpenBLAS reads when it loads.
BLAS_THREADS_VAR = "OPENBLAS_NUM_THREADS"


def blas_on_calling_thread() -> bool:
    """Set ``OPENBLAS_NUM_THREADS=1`` unless the user set it; False when numpy was imported
    already (then the setting would come too late and nothing is changed)."""
    if "numpy" in sys.modules:
        return False
    os.environ.setdefault(BLAS_THREADS_VAR, "1")
    return True
