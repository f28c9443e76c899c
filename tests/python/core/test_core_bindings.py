"""The extension's edge: input validation, zero-copy access, NaN handling, fuzzing.

Nothing a user passes may crash the interpreter: wrong shapes and dtypes raise
TypeError/ValueError naming the argument; NaN/Inf rows are dropped and counted.
"""

import pickle

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from grasp_pipeline import _core


def table_cloud(n=3000, z=0.2, seed=0):
    rng = np.random.default_rng(seed)
    pts = np.column_stack([rng.uniform(0.3, 0.8, n), rng.uniform(-0.3, 0.3, n),
                           z + rng.normal(0, 0.002, n)])
    return pts


def cube_cloud(center, side=0.05, n=1500, z0=0.2, seed=1):
    rng = np.random.default_rng(seed)
    top = np.column_stack([rng.uniform(-side / 2, side / 2, n), rng.uniform(-side / 2, side / 2, n),
                           np.full(n, z0 + side)])
    return top + np.array([center[0], center[1], 0.0])


@pytest.mark.parametrize("bad, exc, words", [
    (np.zeros((10, 2)), ValueError, "(N, 3)"),
    (np.zeros((10,)), ValueError, "(N, 3)"),
    (np.zeros((2, 10, 3)), ValueError, "(N, 3)"),
    (np.zeros((10, 3), dtype=np.int64), TypeError, "float32 or float64"),
    (np.zeros((10, 3), dtype=np.float16), TypeError, "float32 or float64"),
    ([[0.0, 0.0, 0.0]], TypeError, "numpy array"),
    ("not a cloud", TypeError, "numpy array"),
    (np.zeros((0, 3)), ValueError, "empty cloud"),
])
def test_bad_points_raise_naming_the_argument(bad, exc, words):
    f = _core.SceneFilter(_core.SceneFilterParams())
    with pytest.raises(exc) as info:
        f.process(bad)
    assert "points" in str(info.value) and words in str(info.value)


def test_negative_or_absurd_parameters_name_the_parameter():
    p = _core.SceneFilterParams()
    p.cluster_eps = -0.1
    with pytest.raises(ValueError, match="cluster_eps"):
        _core.SceneFilter(p)
    q = _core.ObbParams()
    q.n_theta = 1
    with pytest.raises(ValueError, match="n_theta"):
        _core.Perception(_core.SceneFilterParams(), q)
    p = _core.SceneFilterParams()
    p.plane_max_tilt_deg = 120.0
    with pytest.raises(ValueError, match="plane_max_tilt_deg"):
        p.validate()


def test_nan_rows_are_dropped_counted_and_labelled_invalid():
    pts = table_cloud().astype(np.float32)
    pts[::10] = np.nan
    pts[5, 1] = np.inf
    res = _core.SceneFilter(_core.SceneFilterParams()).process(pts)
    bad = ~np.isfinite(pts).all(axis=1)
    assert res.num_invalid == int(bad.sum())
    assert res.num_valid == len(pts) - int(bad.sum())
    assert len(res.labels) == len(pts)
    assert np.all(res.labels[bad] == _core.LABEL_INVALID)
    assert np.all(res.labels[~bad] != _core.LABEL_INVALID)


def test_float32_float64_and_strided_inputs_agree():
    pts = np.vstack([table_cloud(), cube_cloud((0.55, 0.0))])
    ref = _core.SceneFilter(_core.SceneFilterParams()).process(pts.astype(np.float32))
    wide = np.zeros((len(pts), 5), dtype=np.float32)
    wide[:, 1:4] = pts
    strided = wide[:, 1:4]  # non-contiguous rows, contiguous columns: read in place
    assert not strided.flags.c_contiguous
    res = _core.SceneFilter(_core.SceneFilterParams()).process(strided)
    assert np.array_equal(res.labels, ref.labels)
    fortran = np.asfortranarray(pts.astype(np.float32))  # columns strided: one copy, same answer
    res_f = _core.SceneFilter(_core.SceneFilterParams()).process(fortran)
    assert np.array_equal(res_f.labels, ref.labels)
    res64 = _core.SceneFilter(_core.SceneFilterParams()).process(pts)
    assert res64.table is not None and abs(res64.table.height_m - ref.table.height_m) < 1e-3
    assert np.array_equal(res64.labels >= 0, ref.labels >= 0)


def test_arrays_that_crossed_a_pickle_are_accepted():
    """A process pool or Ray hands over arrays through pickle: their dtype is equal to numpy's
    float32/uint8 but not the same object; every entry point reads them as the originals."""
    pts = np.vstack([table_cloud(), cube_cloud((0.55, 0.0))]).astype(np.float32)
    moved = pickle.loads(pickle.dumps(pts))
    assert moved.dtype == np.float32 and moved.dtype is not np.dtype(np.float32)
    ref = _core.SceneFilter(_core.SceneFilterParams()).process(pts)
    res = _core.SceneFilter(_core.SceneFilterParams()).process(moved)
    assert np.array_equal(res.labels, ref.labels)
    rgb = np.zeros((len(pts), 3), dtype=np.uint8)
    args = (np.array([0.55, 0.0, 0.8]), 0.0, 0)
    a = _core.Perception(_core.SceneFilterParams(), _core.ObbParams()).process(pts, *args, rgb)
    b = _core.Perception(_core.SceneFilterParams(), _core.ObbParams()).process(
        moved, *args, pickle.loads(pickle.dumps(rgb)))
    assert np.array_equal(a.filter.labels, b.filter.labels) and a.tids == b.tids and a.tids


def test_labels_are_a_read_only_view_that_outlives_nothing():
    res = _core.SceneFilter(_core.SceneFilterParams()).process(table_cloud().astype(np.float32))
    labels = res.labels
    del res
    assert labels.dtype == np.int32 and not labels.flags.writeable
    assert np.all(labels == _core.LABEL_ENVIRONMENT)


def test_estimate_and_grasp_reject_bad_vectors():
    plane = _core.Plane([0, 0, 1], -0.2)
    with pytest.raises(ValueError, match="theta_prev"):
        _core.estimate_object(cube_cloud((0.5, 0)), plane, _core.ObbParams(), theta_prev=float("nan"))
    with pytest.raises(ValueError, match="camera_position"):
        _core.assess_view([0.5, 0, 0.2], [np.nan, 0, 0.6], [0, 0, 1], 5.0)
    with pytest.raises(ValueError, match="n"):
        _core.Plane([0, 0, 0], 0.1)
    with pytest.raises(ValueError, match="rotation"):
        _core.Pose(np.diag([1.0, 1.0, -1.0]), [0, 0, 0])
    per = _core.Perception(_core.SceneFilterParams(), _core.ObbParams())
    per.process(table_cloud(), [0.3, 0.0, 0.6], 1.0)
    with pytest.raises(ValueError, match="backwards"):
        per.process(table_cloud(), [0.3, 0.0, 0.6], 0.5)


finite = st.floats(-5, 5, allow_nan=False, width=32)
any_float = st.floats(allow_nan=True, allow_infinity=True, width=32)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(hnp.arrays(np.float32, st.tuples(st.integers(1, 400), st.just(3)), elements=any_float))
def test_fuzz_scene_filter_never_crashes(pts):
    res = _core.SceneFilter(_core.SceneFilterParams()).process(pts)
    assert len(res.labels) == len(pts)
    assert res.num_valid + res.num_invalid == len(pts)


@settings(max_examples=60, deadline=None)
@given(hnp.arrays(np.float64, st.tuples(st.integers(1, 200), st.just(3)), elements=any_float),
       st.one_of(st.none(), st.floats(-10, 10)))
def test_fuzz_estimate_never_crashes(pts, theta_prev):
    plane = _core.Plane([0, 0, 1], -0.2)
    res = _core.estimate_object(pts, plane, _core.ObbParams(), theta_prev=theta_prev, band=0.01)
    assert (res.estimate is None) == (res.failure != "")
    if res.estimate is not None:
        assert abs(np.linalg.det(res.estimate.R_box) - 1) < 1e-9


@settings(max_examples=40, deadline=None)
@given(hnp.arrays(np.float64, st.tuples(st.integers(0, 60), st.just(3)), elements=finite))
def test_fuzz_pca_and_clusters_never_crash(pts):
    box = _core.pca_box(pts)
    if box is not None:
        assert abs(np.linalg.det(box.R) - 1) < 1e-9
    if len(pts):
        res = _core.euclidean_clusters(pts, 0.015, 2, 0.0, 0.3, 0.003)
        assert len(res.labels) == len(pts)


@settings(max_examples=40, deadline=None)
@given(st.lists(finite, min_size=0, max_size=50), st.floats(-10, 10))
def test_fuzz_angle_helpers(angles, ref):
    m = _core.circular_median_mod_pi(angles, ref)
    assert 0 <= m < np.pi
    ext = [abs(a) + 0.01 for a in angles]
    if ext:
        choice = _core.choose_direction(ext, 0.002, None)
        assert 0 <= choice.theta_rad < np.pi


def test_tracks_are_copies_that_survive_later_frames():
    """Regression: `tracker.tracks` once returned references into the C++ vector, which the
    next update reallocated — held tracks then read freed memory (garbage boxes)."""
    per = _core.Perception(_core.SceneFilterParams(), _core.ObbParams())
    cloud = np.vstack([table_cloud(20000), cube_cloud((0.45, -0.1), seed=2), cube_cloud((0.6, 0.1), seed=3)])
    per.process(cloud, [0.3, 0.0, 0.6], 0.0)
    held = per.tracker.tracks
    centres = [np.array(t.smoothed.center) for t in held]
    views = [t.smoothed.center for t in held]  # numpy views tied to the copies
    for k in range(1, 40):  # tracks retire and new ones are created meanwhile
        shifted = cloud + np.array([0.3 * (k % 2), 0.0, 0.0])
        per.process(shifted, [0.3, 0.0, 0.6], 3.0 * k)
    for c, v in zip(centres, views):
        assert np.array_equal(np.asarray(v), c)
    state = per.scene_filter.persistence.state
    hits = state.hits
    per.process(cloud, [0.3, 0.0, 0.6], 200.0)
    assert state.hits == hits  # a snapshot, not a live view
