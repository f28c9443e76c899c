"""Products in row blocks are the products of one call, bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from grasp_pipeline.motion.matmul_blocks import BLOCK_MULTIPLY_ADDS, matmul_rows


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_blocks_equal_one_product_on_random_shapes(dtype):
    rng = np.random.default_rng(0 if dtype == np.float32 else 1)
    blocked = 0
    for trial in range(45):
        m = int(rng.choice([rng.integers(1, 40), rng.integers(40, 3000), rng.integers(5000, 30000)]))
        n = int(rng.choice([rng.integers(1, 12), rng.integers(12, 1200)]))
        a = (rng.normal(size=(m, 3)) * rng.uniform(0.01, 10.0)).astype(dtype)
        b = rng.normal(size=(3, n)).astype(dtype)
        if trial % 3 == 0:
            b = np.asfortranarray(b)  # a transposed operand (a box's axes, say)
        got = matmul_rows(a, b)
        want = a @ b
        assert got.dtype == want.dtype and got.flags["C_CONTIGUOUS"]
        assert np.array_equal(got, want), (m, n, dtype)
        blocked += m * n * 3 > BLOCK_MULTIPLY_ADDS and n > 1
    assert blocked > 10  # many trials did run in blocks


def test_a_last_block_of_one_row_is_not_made():
    rng = np.random.default_rng(2)
    n = 1000
    rows = BLOCK_MULTIPLY_ADDS // (3 * n)
    a, b = rng.normal(size=(3 * rows + 1, 3)), rng.normal(size=(3, n))
    assert np.array_equal(matmul_rows(a, b), a @ b)


def test_other_shapes_are_plain_products():
    rng = np.random.default_rng(3)
    a, v = rng.normal(size=(50000, 3)), rng.normal(size=(3, 1))
    assert np.array_equal(matmul_rows(a, v), a @ v)
    stack = rng.normal(size=(4, 10, 3))
    assert np.array_equal(matmul_rows(stack, np.eye(3)), stack @ np.eye(3))
