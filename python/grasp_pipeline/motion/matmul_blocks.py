"""Thin matrix products (points times a few axes) in row blocks that BLAS runs on the caller's
thread.

A product of many points (M, 3) by a few axes (3, N) — a box's frame, the candidate grasp
frames — is over OpenBLAS's threading threshold (m·n·k above 65536·4 multiply-adds) while taking
well under a millisecond: waking the library's worker threads for it costs more CPU than the
product, many times more on a loaded machine (they spin while they wait). Cut into blocks of rows
under the threshold, each block runs on the calling thread with the same kernel: every element
is the same float as in one call (the tests compare them bit for bit). Blocks of one row, which
BLAS would take as a matrix-vector product (another kernel), are never made.
"""

from __future__ import annotations

import numpy as np

#: Multiply-adds of one block: a quarter of OpenBLAS's single-thread limit (65536 · 4).
BLOCK_MULTIPLY_ADDS = 65536


def matmul_rows(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``a @ b`` for ``a`` (M, K) and ``b`` (K, N), computed in blocks of rows of at most
    :data:`BLOCK_MULTIPLY_ADDS` multiply-adds (module doc); other shapes as ``a @ b``."""
    a, b = np.asarray(a), np.asarray(b)
    if a.ndim != 2 or b.ndim != 2 or b.shape[1] < 2:
        return a @ b
    m, k = a.shape
    n = b.shape[1]
    rows = max(2, BLOCK_MULTIPLY_ADDS // max(1, k * n))
    if m <= rows:
        return a @ b
    out = np.empty((m, n), dtype=np.result_type(a, b))
    for start in range(0, m, rows):
        stop = min(m, start + rows)
        start = min(start, stop - 2)  # the last block has two rows at least
        np.matmul(a[start:stop], b, out=out[start:stop])
    return out
