"""The scene cloud: per-point owners from a frame's labels (cluster → estimate → track)."""

import re
import types

import numpy as np
import pytest

from grasp_pipeline import _core
from grasp_pipeline.orchestration.scene.scene_cloud import ENVIRONMENT, UNTRACKED, cloud_from_frame


def _frame(points, labels, estimate_labels, tids, emitted=True):
    labels = np.asarray(labels)
    raw = types.SimpleNamespace(estimate_labels=estimate_labels, tids=tids)
    env = (labels == -1) if emitted else np.zeros(len(labels), dtype=bool)
    return types.SimpleNamespace(points=np.asarray(points, float), labels=labels, raw=raw,
                                 environment_mask=env, environment_emitted=emitted)


PLANE = types.SimpleNamespace(n=[0.0, 0.0, 1.0], c=-0.2)


def test_points_take_the_track_of_their_cluster_and_invalid_rows_are_dropped():
    pts = [[0.5, 0, 0.25], [0.6, 0, 0.24], [0.7, 0, 0.2], [np.nan, 0, 0], [0.8, 0, 0.23]]
    fr = _frame(pts, [0, 1, -1, -2, 2], estimate_labels=[1, 0], tids=[7, 3])
    cloud = cloud_from_frame(fr, PLANE, 0.01, 0.001)
    owners = {tuple(np.round(p, 3)): int(o) for p, o in zip(cloud.points, cloud.owner)}
    assert owners == {(0.5, 0.0, 0.25): 3, (0.6, 0.0, 0.24): 7, (0.7, 0.0, 0.2): ENVIRONMENT,
                      (0.8, 0.0, 0.23): UNTRACKED}
    assert np.allclose(cloud.heights_m(np.array([[0.5, 0, 0.25]])), 0.05)
    assert len(cloud.near((0.5, 0.0), 0.05)) == 1 and len(cloud.of(7)) == 1


def test_environment_is_left_out_until_the_filter_emits_it():
    fr = _frame([[0.5, 0, 0.25], [0.7, 0, 0.2]], [0, -1], [0], [4], emitted=False)
    cloud = cloud_from_frame(fr, PLANE, 0.01, 0.001)
    assert cloud.owner.tolist() == [4]


def voxel_thin(points, owner, voxel_m):
    """The core's thinning of finite points with owners: the first point of each (voxel, owner) pair."""
    first = _core.first_per_voxel(np.ascontiguousarray(points, dtype=np.float64),
                                  np.ascontiguousarray(owner, dtype=np.int64), float(voxel_m))
    return np.take(points, first, axis=0), np.take(owner, first)


def test_voxel_thinning_keeps_one_point_per_voxel_and_owner():
    pts = np.array([[0.0, 0, 0], [0.001, 0, 0], [0.001, 0, 0], [0.01, 0, 0]])
    own = np.array([1, 1, 2, 1])
    p, o = voxel_thin(pts, own, 0.003)
    assert len(p) == 3 and sorted(o.tolist()) == [1, 1, 2]


def _unique_thin(points, owner, voxel_m):
    """The thinning as one np.unique over the (voxel, owner) key: what the core keeps."""
    ii = np.floor(points / voxel_m).astype(np.int64)
    ii -= ii.min(axis=0)
    dims = ii.max(axis=0) + 1
    key = ((ii[:, 0] * dims[1] + ii[:, 1]) * dims[2] + ii[:, 2]) * (int(owner.max() - owner.min()) + 1)
    _, first = np.unique(key + owner - owner.min(), return_index=True)
    return points[first], owner[first]


def _frame_like(seed, n=20000):
    """Points in a 0.4 m box with many per voxel, NaN rows, labels of 3 clusters / environment
    / dropped."""
    rng = np.random.default_rng(seed)
    pts = rng.uniform(-0.2, 0.2, (n, 3)).astype(np.float32) + np.float32([0.5, 0.0, 0.3])
    pts[rng.random(n) < 0.05] = np.nan
    labels = rng.integers(-3, 3, n)
    return pts, labels


def test_voxel_thin_returns_what_np_unique_returns():
    for seed, voxel_m in ((0, 0.003), (1, 0.02), (2, 1e-9)):  # 1e-9: keys too large to pack
        pts, labels = _frame_like(seed)
        pts = pts[np.isfinite(pts[:, 0])].astype(float)
        owner = labels[:len(pts)].astype(np.int64)
        got, expected = voxel_thin(pts, owner, voxel_m), _unique_thin(pts, owner, voxel_m)
        assert len(got[0]) < len(pts) or voxel_m < 1e-6
        for a, b in zip(got, expected):
            np.testing.assert_array_equal(a, b)


def test_cloud_from_frame_keeps_the_rows_a_full_float_copy_would_keep():
    pts, labels = _frame_like(3)
    fr = _frame(pts, labels, estimate_labels=[0, 2], tids=[5, 9])
    fr.points = pts  # float32, as the perception core gives them
    cloud = cloud_from_frame(fr, PLANE, 0.01, 0.003)
    full = pts.astype(float)
    owner = np.select([labels == 0, labels == 2, labels == 1, labels == -1],
                      [5, 9, UNTRACKED, ENVIRONMENT], -99)
    keep = (labels >= -1) & np.all(np.isfinite(full), axis=1)
    expected = _unique_thin(full[keep], owner[keep], 0.003)
    np.testing.assert_array_equal(cloud.points, expected[0])
    np.testing.assert_array_equal(cloud.owner, expected[1])


def _numpy_cloud(pts, labels, lut, emitted, voxel_m):
    """The scene cloud's rows computed with numpy alone: owners from the labels, the rows with
    an owner and finite coordinates as float64, then np.unique's thinning."""
    owner = np.full(len(labels), -99, dtype=np.int64)
    obj = labels >= 0
    owner[obj] = [lut.get(int(lab), UNTRACKED) for lab in labels[obj]]
    if emitted:
        owner[labels == -1] = ENVIRONMENT
    full = pts.astype(float)
    keep = (owner != -99) & np.all(np.isfinite(full), axis=1)
    return _unique_thin(full[keep], owner[keep], voxel_m)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("emitted", [True, False])
@pytest.mark.parametrize("estimates", [([0, 2], [5, 9]), ([], []), ([1, -1, 7], [4, 8, 6])])
def test_the_core_keeps_the_rows_numpy_keeps(dtype, emitted, estimates):
    pts, labels = _frame_like(4)
    pts = pts.astype(dtype)
    pts[7, 1], pts[11, 2] = np.inf, np.nan  # rows with one coordinate not finite
    fr = _frame(pts, labels, estimate_labels=estimates[0], tids=estimates[1], emitted=emitted)
    fr.points = pts
    lut = {lab: tid for lab, tid in zip(*estimates) if lab >= 0}
    for voxel_m in (0.003, 0.02, 1e-9):
        cloud = cloud_from_frame(fr, PLANE, 0.01, voxel_m)
        expected = _numpy_cloud(pts, labels, lut, emitted, voxel_m)
        assert cloud.points.dtype == np.float64 and cloud.owner.dtype == np.int64
        np.testing.assert_array_equal(cloud.points, expected[0])
        np.testing.assert_array_equal(cloud.owner, expected[1])


def test_the_core_row_thinning_refuses_bad_arrays_by_name():
    pts, labels = np.zeros((4, 3), dtype=np.float32), np.zeros(4, dtype=np.int32)
    good = dict(owner_of_label=[1], environment_emitted=True, environment_owner=-1,
                untracked_owner=-2, environment_label=-1, voxel_m=0.01)
    cases = [((pts, labels.astype(np.int64)), {}, TypeError, "labels: expected dtype int32"),
             ((pts, labels[:3]), {}, ValueError, "labels: expected shape (4)"),
             ((pts[:, :2].copy(), labels), {}, ValueError, "points: expected shape (n, 3)"),
             ((pts, labels), {"voxel_m": -1.0}, ValueError, "voxel_m: expected a positive")]
    for args, change, exc, text in cases:
        with pytest.raises(exc, match=re.escape(text)):
            _core.thin_owned_rows(*args, **{**good, **change})
    p, o = _core.thin_owned_rows(pts[:0], labels[:0], **good)
    assert p.shape == (0, 3) and o.shape == (0,)


def test_the_core_thinning_refuses_bad_arrays_by_name():
    from grasp_pipeline import _core

    pts, own = np.zeros((4, 3)), np.zeros(4, dtype=np.int64)
    bad = pts.copy()
    bad[2, 1] = np.nan
    cases = [((pts.astype(np.float32), own, 0.01), TypeError, "points: expected dtype float64"),
             ((pts, own[:3], 0.01), ValueError, "owner: expected shape (4)"),
             ((bad, own, 0.01), ValueError, "row 2 is not finite"),
             ((pts, own, 0.0), ValueError, "voxel_m: expected a positive")]
    for args, exc, text in cases:
        with pytest.raises(exc, match=re.escape(text)):
            _core.first_per_voxel(*args)
