"""The occupancy map's cheaper paths give exactly what the plain computations give."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

from grasp_pipeline.motion.exceptions import EnvironmentCloudError
from grasp_pipeline.motion.occupancy import OccupancyMap, OrientedBox, distance_field_m
from grasp_pipeline.motion.thin_matmul import thin_matmul


def _reference_field(occupied: np.ndarray, voxel_m: float) -> np.ndarray:
    """The distance field as scipy's Euclidean distance transform gives it."""
    return (ndimage.distance_transform_edt(~occupied) * voxel_m).astype(np.float32)


@pytest.mark.parametrize("shape, fill", [((30, 41, 17), 0.01), ((5, 60, 9), 0.2), ((1, 1, 1), 1.0),
                                         ((12, 3, 1), 0.05), ((25, 25, 25), 0.001)])
@pytest.mark.parametrize("voxel_m", [0.01, 0.0075, 0.02])
def test_distance_field_equals_scipy_transform(shape, fill, voxel_m):
    rng = np.random.default_rng(len(shape) + int(fill * 1000))
    occupied = rng.random(shape) < fill
    occupied.flat[rng.integers(occupied.size)] = True
    field = distance_field_m(occupied, voxel_m)
    assert field.dtype == np.float32 and field.shape == occupied.shape
    assert np.array_equal(field, _reference_field(occupied, voxel_m))


def test_map_field_equals_scipy_transform_on_a_table_cloud():
    rng = np.random.default_rng(3)
    xy = rng.uniform([0.2, -0.4], [0.9, 0.4], size=(20000, 2))
    table = np.c_[xy, rng.normal(0.0, 0.002, len(xy))]
    box = rng.uniform([0.4, -0.1, 0.0], [0.5, 0.0, 0.08], size=(3000, 3))
    pts = np.vstack([table, box, [[np.nan, 0.0, 0.0], [5.0, 5.0, 5.0]]])
    m = OccupancyMap.from_points(pts, 0.01, [-1.2, -1.2, -0.2], [1.4, 1.4, 1.4], pad_m=0.1,
                                 max_points=10**6, max_voxels=10**7)
    assert np.array_equal(m.distance_field_m, _reference_field(m.occupied, 0.01))
    # every finite point inside the workspace is kept, none other
    assert len(m._points) == len(table) + len(box)


def test_cleared_view_is_built_once_per_box_and_equals_a_fresh_one():
    rng = np.random.default_rng(4)
    pts = rng.uniform([0.3, -0.2, 0.0], [0.7, 0.2, 0.1], size=(5000, 3))
    m = OccupancyMap.from_points(pts, 0.01, [-1.0] * 3, [1.0] * 3, pad_m=0.1, max_points=10**6,
                                 max_voxels=10**7)
    box = OrientedBox(np.array([0.5, 0.0, 0.05]), np.eye(3), np.array([0.06, 0.04, 0.1]))
    view = m.with_cleared_region(box)
    same = m.with_cleared_region(OrientedBox(box.center.copy(), box.R.copy(), box.extents.copy()))
    other = m.with_cleared_region(box.inflated(0.01))
    assert same is view and other is not view
    fresh = OccupancyMap.from_points(pts, 0.01, [-1.0] * 3, [1.0] * 3, pad_m=0.1, max_points=10**6,
                                     max_voxels=10**7).with_cleared_region(box)
    q = rng.uniform([0.3, -0.2, 0.0], [0.7, 0.2, 0.15], size=(2000, 3))
    assert np.array_equal(view.distance_m(q, cleared=True), fresh.distance_m(q, cleared=True))
    assert np.array_equal(view.cleared_region()[1], fresh.cleared_region()[1])
    assert m.cleared_region() is None  # the map itself stays plain


def test_non_finite_and_outside_points_are_dropped():
    pts = np.array([[0.1, 0.2, 0.3], [np.nan, 0.0, 0.0], [np.inf, 0.0, 0.0], [0.0, -np.inf, 0.0],
                    [0.3, 0.2, 0.1], [2.0, 0.0, 0.0]])
    m = OccupancyMap.from_points(pts, 0.01, [-1.0] * 3, [1.0] * 3, pad_m=0.05, max_points=100,
                                 max_voxels=10**7)
    assert m._points is not pts and np.array_equal(m._points, pts[[0, 4]])
    inside = pts[[0, 4]]
    m = OccupancyMap.from_points(inside, 0.01, [-1.0] * 3, [1.0] * 3, pad_m=0.05, max_points=100,
                                 max_voxels=10**7)
    assert m._points is not inside and np.array_equal(m._points, inside)  # its own copy


def _reference_grid(pts, v, lo, hi, pad_m):
    """(origin, occupied, kept points) as the array formulation voxelises a cloud."""
    pts = pts[np.all(np.isfinite(pts), axis=1)]
    pts = pts[np.all((pts >= lo) & (pts <= hi), axis=1)]
    pad_vox = int(np.ceil(pad_m / v)) + 1
    idx = np.floor((pts - lo) / v).astype(np.int64)
    imin, imax = idx.min(axis=0) - pad_vox, idx.max(axis=0) + pad_vox
    occ = np.zeros(tuple(imax - imin + 1), dtype=bool)
    occ[tuple((idx - imin).T)] = True
    return lo + imin * v, occ, pts


@pytest.mark.parametrize("seed", range(4))
def test_voxel_grid_equals_the_array_formulation(seed):
    rng = np.random.default_rng(seed)
    v = [0.01, 0.0075, 0.013, 0.02][seed]
    pts = rng.uniform(-0.7, 0.7, size=(4000, 3))
    pts[rng.integers(len(pts), size=40), rng.integers(3, size=40)] = np.nan
    pts[rng.integers(len(pts), size=20), rng.integers(3, size=20)] = -np.inf
    lo, hi = np.array([-0.5, -0.6, -0.45]), np.array([0.55, 0.5, 0.6])
    pts[:30] = np.round(pts[:30] / v) * v  # on voxel faces
    pts[30], pts[31] = lo, hi  # on the workspace's corners
    m = OccupancyMap.from_points(pts, v, lo, hi, pad_m=0.05, max_points=10**5, max_voxels=10**7)
    origin, occ, kept = _reference_grid(pts, v, lo, hi, 0.05)
    assert np.array_equal(m.origin_m, origin)
    assert np.array_equal(m.occupied, occ)
    assert np.array_equal(m._points, kept)


def test_an_oversized_grid_is_refused_with_its_size():
    pts = np.array([[0.0, 0.0, 0.0], [0.5, 0.5, 0.5]])
    with pytest.raises(EnvironmentCloudError, match=r"occupancy grid would need \d+ voxels .*max_grid_voxels"):
        OccupancyMap.from_points(pts, 0.01, [-1.0] * 3, [1.0] * 3, pad_m=0.05, max_points=100, max_voxels=1000)


def test_box_queries_equal_the_products_in_fixed_order():
    rng = np.random.default_rng(9)
    R = np.linalg.qr(rng.normal(size=(3, 3)))[0].T  # a transposed (F order) rotation, as boxes get
    box = OrientedBox(np.array([0.5, 0.0, 0.1]), R, np.array([0.06, 0.04, 0.1]))
    pts = box.center + rng.normal(0.0, 0.05, size=(60000, 3))
    local = thin_matmul(pts - box.center, box.R)  # the same sums as box.R's C-order copy
    assert np.array_equal(box.contains(pts), np.all(np.abs(local) <= 0.5 * box.extents, axis=-1))
    h = 0.5 * box.extents
    assert np.array_equal(box.distance_m(pts), np.linalg.norm(local - np.clip(local, -h, h), axis=-1))
    assert box.contains(box.center) and box.distance_m(box.center[None])[0] == 0.0



def test_the_core_transform_refuses_what_is_not_a_3d_bool_grid():
    from grasp_pipeline import _core

    with pytest.raises(TypeError, match="occupied: expected dtype bool"):
        _core.squared_distance_transform(np.zeros((3, 3, 3), dtype=np.uint8))
    with pytest.raises(ValueError, match=r"occupied: expected shape \(n, n, n\)"):
        _core.squared_distance_transform(np.zeros((3, 3), dtype=bool))
    assert (_core.squared_distance_transform(np.zeros((2, 2, 2), dtype=bool)) == -1).all()
    with pytest.raises(TypeError, match="occupied: expected dtype bool"):
        _core.distance_field(np.zeros((3, 3, 3), dtype=np.uint8), 0.01)
    with pytest.raises(ValueError, match="voxel_m must be a finite size"):
        _core.distance_field(np.ones((2, 2, 2), dtype=bool), 0.0)
    assert np.isposinf(_core.distance_field(np.zeros((2, 2, 2), dtype=bool), 0.01)).all()


def test_the_core_voxelisation_refuses_malformed_input():
    from grasp_pipeline import _core

    lo, hi = np.full(3, -1.0), np.full(3, 1.0)
    with pytest.raises(TypeError, match="points: expected dtype float64"):
        _core.voxelize_points(np.zeros((4, 3), dtype=np.float32), lo, hi, 0.01, 2, 10**6)
    with pytest.raises(ValueError, match=r"lo: expected shape \(3\)"):
        _core.voxelize_points(np.zeros((4, 3)), np.zeros(2), hi, 0.01, 2, 10**6)
    with pytest.raises(ValueError, match="voxel_m must be a finite size"):
        _core.voxelize_points(np.zeros((4, 3)), lo, hi, np.nan, 2, 10**6)
    kept, first, shape, occ = _core.voxelize_points(np.full((2, 3), 5.0), lo, hi, 0.01, 2, 10**6)
    assert kept.shape == (0, 3) and occ is None
