"""Thin matrix products — many points (M, 3) times a few axes (3, N): a box's frame, the
candidate grasp frames — computed by the C++ core on the calling thread, each element summed in
one fixed order without fused multiply-add (``(a[i, 0] b[0, j] + a[i, 1] b[1, j]) + a[i, 2]
b[2, j]`` in the operands' precision).

A BLAS call is no good here twice over: OpenBLAS wakes its worker threads for such a product
(over its threading threshold while taking well under a millisecond), which costs more CPU
than the product; and its kernels and blocking depend on the CPU and the thread count, so the
same product can differ in the last bit from one machine, or one thread count, to another.
These products give the same floats everywhere (the tests compare them with the numpy
formulation of the same sums).
"""

from __future__ import annotations

import numpy as np

from .. import _core


def thin_matmul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``a @ b`` for ``a`` (M, K) and ``b`` (K, N) of one dtype, float32 or float64, summed as
    the module doc says; other shapes, dtypes and empty operands as ``a @ b``."""
    a, b = np.asarray(a), np.asarray(b)
    if (a.ndim != 2 or b.ndim != 2 or a.dtype != b.dtype or a.dtype not in (np.float32, np.float64)
            or a.size == 0 or b.size == 0 or a.shape[1] != b.shape[0]):
        return a @ b
    return _core.thin_matmul(np.ascontiguousarray(a), np.ascontiguousarray(b))
