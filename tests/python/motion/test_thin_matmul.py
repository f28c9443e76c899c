"""Thin products are the numpy formulation of the same sums, bit for bit, on any machine."""

from __future__ import annotations

import numpy as np
import pytest

from grasp_pipeline.motion.thin_matmul import thin_matmul


def _sums(a, b):
    """``a @ b`` as separate multiplies and adds in the order k = 0, 1, ... (no fused ops)."""
    out = a[:, :1] * b[0]
    for k in range(1, a.shape[1]):
        out = out + a[:, k:k + 1] * b[k]
    return out


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_products_are_the_sums_in_order_on_random_shapes(dtype):
    rng = np.random.default_rng(0 if dtype == np.float32 else 1)
    for trial in range(40):
        m = int(rng.choice([rng.integers(1, 40), rng.integers(40, 3000), rng.integers(5000, 30000)]))
        n = int(rng.choice([rng.integers(1, 12), rng.integers(12, 1200)]))
        k = 3 if trial % 4 else int(rng.integers(1, 6))
        a = (rng.normal(size=(m, k)) * rng.uniform(0.01, 10.0)).astype(dtype)
        b = rng.normal(size=(k, n)).astype(dtype)
        if trial % 3 == 0:
            b = np.asfortranarray(b)  # a transposed operand (a box's axes, say)
        got = thin_matmul(a, b)
        assert got.dtype == dtype and got.shape == (m, n) and got.flags["C_CONTIGUOUS"]
        np.testing.assert_array_equal(got, _sums(a, b))
        # and the product itself: within the rounding bound of k products and k - 1 sums
        exact = a.astype(np.float64) @ b.astype(np.float64)
        bound = 2 * k * np.finfo(dtype).eps * (np.abs(a).astype(np.float64) @ np.abs(b).astype(np.float64))
        assert np.all(np.abs(got - exact) <= bound)


def test_other_operands_are_plain_products():
    rng = np.random.default_rng(3)
    a = rng.normal(size=(50, 3))
    stack = rng.normal(size=(4, 5, 3))
    assert np.array_equal(thin_matmul(stack, np.eye(3)), stack @ np.eye(3))
    assert np.array_equal(thin_matmul(a, np.eye(3, dtype=np.float32)), a @ np.eye(3, dtype=np.float32))
    assert thin_matmul(np.zeros((0, 3)), np.eye(3)).shape == (0, 3)


def test_the_core_refuses_mismatched_operands():
    from grasp_pipeline import _core

    with pytest.raises(ValueError, match=r"b: expected shape \(3, n\)"):
        _core.thin_matmul(np.zeros((4, 3)), np.zeros((2, 5)))
    with pytest.raises(TypeError, match="b: expected dtype float64"):
        _core.thin_matmul(np.zeros((4, 3)), np.zeros((3, 5), dtype=np.float32))
