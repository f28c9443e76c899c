"""Hypothesis fuzz of every binding that takes points, over the full float range.

Values: +-float32/float64 max, subnormals, +-0, NaN, +-Inf, values at the coordinate bound,
ordinary workspace numbers; clouds: tiny (0-3 rows), small random, huge counts of one
duplicated row, optionally on a table so that the plane locks and clustering runs. The
invariant is that nothing crashes (an abort kills the run) and results are well formed.

CI runs GRASP_FUZZ_EXAMPLES examples (default 200, a few seconds); a long run:

    GRASP_FUZZ_EXAMPLES=20000 PYTHONPATH=python .venv/bin/python -m pytest -q \\
        tests/python/core/test_fuzz_full_range.py --hypothesis-show-statistics
"""

import os

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from grasp_pipeline import _core
from test_core_bindings import table_cloud

EXAMPLES = int(os.environ.get("GRASP_FUZZ_EXAMPLES", "200"))
MAX_DUPLICATES = int(os.environ.get("GRASP_FUZZ_MAX_DUPLICATES", "20000"))

F32, F64 = np.finfo(np.float32), np.finfo(np.float64)
EDGE_VALUES = [0.0, -0.0, np.nan, np.inf, -np.inf, float(F32.max), -float(F32.max), float(F32.tiny),
           float(F32.smallest_subnormal), -float(F32.smallest_subnormal), float(F64.max),
           -float(F64.max), float(F64.smallest_subnormal), 1000.0, -1000.0, 1000.0001, 1e-30,
           0.2, 0.25, 3.4e38, -3.4e38, 1.7e38]
VALUES = st.one_of(st.sampled_from(EDGE_VALUES), st.floats(allow_nan=True, allow_infinity=True),
                   st.floats(-2.0, 2.0), st.floats(0.19, 0.3))
ROW = st.tuples(VALUES, VALUES, VALUES)
TABLE = table_cloud(2000, seed=5)


@st.composite
def clouds(draw):
    kind = draw(st.sampled_from(["tiny", "random", "duplicated", "mixed"]))
    if kind == "tiny":
        rows = draw(st.lists(ROW, min_size=0, max_size=3))
    elif kind == "random":
        rows = draw(st.lists(ROW, min_size=1, max_size=80))
    else:
        rows = [draw(ROW)] * draw(st.integers(16, MAX_DUPLICATES))
        if kind == "mixed":
            rows += draw(st.lists(ROW, min_size=0, max_size=20))
    pts = np.array(rows, dtype=np.float64).reshape(-1, 3)
    if draw(st.booleans()):
        pts = np.vstack([TABLE, pts])
    dtype = draw(st.sampled_from([np.float32, np.float64]))
    with np.errstate(over="ignore", invalid="ignore"):
        return pts.astype(dtype)


def check_filter_result(res, n):
    assert len(res.labels) == n and res.num_valid + res.num_invalid == n
    assert 0 <= res.num_out_of_range <= res.num_invalid


def check_estimate(r):
    assert (r.estimate is None) == (r.failure != "")
    if r.estimate is not None:
        e = r.estimate
        assert abs(np.linalg.det(e.R_box) - 1) < 1e-6 and np.all(np.asarray(e.extents) >= 0)
        assert np.isfinite(e.center).all() and e.height_m >= 0


def fuzz_scene_filter(pts, voxel):
    params = _core.SceneFilterParams()
    params.cluster_voxel_m = voxel
    if not len(pts):  # documented refusal of an empty frame
        with pytest.raises(ValueError, match="empty cloud"):
            _core.SceneFilter(params).process(pts)
        return
    check_filter_result(_core.SceneFilter(params).process(pts), len(pts))
    fit = _core.fit_plane_ransac(pts, params)
    assert fit is None or abs(np.linalg.norm(fit.plane.n) - 1) < 1e-9
    if len(pts):
        for cand in _core.extract_planes(pts, params):
            assert 0 <= cand.count_whole <= len(pts)
        cl = _core.euclidean_clusters(pts, 0.015, 2, 0.0, 0.3, voxel)
        assert len(cl.labels) == len(pts) and cl.num_out_of_range <= cl.num_invalid


def fuzz_estimates(pts):
    plane = _core.Plane([0, 0, 1], -0.2)
    box = _core.pca_box(pts)
    assert box is None or abs(np.linalg.det(box.R) - 1) < 1e-6
    assert (box is None) == (_core.pca_box_failure(pts) != "")
    if len(pts):
        check_estimate(_core.estimate_object(pts, plane, _core.ObbParams(), band=0.01))
        tracker = _core.Tracker(_core.ObbParams())
        for r in _core.estimate_with_priors([pts, pts[::2]], plane, _core.ObbParams(), tracker, band=0.01):
            check_estimate(r)


@settings(max_examples=EXAMPLES, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                 HealthCheck.large_base_example])
@given(pts=clouds(), voxel=st.sampled_from([0.003, 0.0]))
def test_fuzz_bindings_over_the_full_float_range(pts, voxel):
    fuzz_scene_filter(pts, voxel)
    fuzz_estimates(pts)
    if len(pts):
        per = _core.Perception(_core.SceneFilterParams(), _core.ObbParams())
        for t in (0.0, 0.1):
            fr = per.process(pts, [0.5, 0.0, 0.6], t)
            check_filter_result(fr.filter, len(pts))
            assert len(fr.estimates) == len(fr.views) == len(fr.tids)
            for e in fr.estimates:
                assert np.isfinite(e.center).all() and e.height_m >= 0
