"""Row selection: the rows boolean indexing selects, in the same order, for every dtype."""

import numpy as np

from grasp_pipeline.array_rows import rows_where


def test_rows_where_is_boolean_indexing():
    rng = np.random.default_rng(0)
    for dtype in (np.float32, np.float64, np.int64, bool):
        a = (rng.normal(size=(1000, 3)) * 10).astype(dtype)
        for frac in (0.0, 0.3, 1.0):
            mask = rng.random(1000) < frac
            got = rows_where(a, mask)
            assert got.dtype == a.dtype and got.shape == a[mask].shape
            np.testing.assert_array_equal(got, a[mask])
    assert rows_where(np.zeros((0, 3)), np.zeros(0, dtype=bool)).shape == (0, 3)
    col = np.arange(5.0)
    np.testing.assert_array_equal(rows_where(col, col > 2), [3.0, 4.0])
