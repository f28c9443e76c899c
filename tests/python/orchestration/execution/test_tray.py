"""The tray's contents: released objects dropped onto what is under them, refreshed by looks."""

import re

import numpy as np
import pytest

from grasp_pipeline.orchestration.execution.tray import TrayContents, TrayGeometry

from .tray_cell import CELL, FLOOR_Z, box_points, floor_points, solid_points

CELL_M = 0.005


def contents():
    return TrayContents(TrayGeometry.from_work_cell(CELL), CELL_M, 0.008)


def test_the_geometry_has_the_four_walls_and_their_height():
    g = TrayGeometry.from_work_cell(CELL)
    assert len(g.walls) == 4  # the stand and the floor are not higher than the floor
    assert g.rim_m == pytest.approx(0.03)
    grid = g.grid(0.01)
    walls = grid.wall_mask()
    assert walls[0].all() and walls[-1].all() and walls[:, 0].all() and walls[:, -1].all()
    assert not walls[2:-2, 2:-2].any()


def test_a_released_object_drops_onto_the_floor_then_the_next_onto_it():
    tray = contents()
    a = tray.add_released(solid_points(0.05, 0.05, 0.04) + [0.34, 0.58, FLOOR_Z + 0.07])
    box = a.box(FLOOR_Z)
    assert a.name == "placed/0"
    assert box.center[2] + box.extents[2] / 2 == pytest.approx(FLOOR_Z + 0.04, abs=CELL_M)
    b = tray.add_released(solid_points(0.03, 0.03, 0.02) + [0.34, 0.58, FLOOR_Z + 0.12])
    assert b.name == "placed/1"
    assert b.tops[:, 2].max() == pytest.approx(FLOOR_Z + 0.04 + 0.02, abs=2 * CELL_M)  # stacked on a


def test_a_look_refreshes_moves_and_forgets_what_it_saw():
    tray = contents()
    tray.add_released(solid_points(0.05, 0.05, 0.05) + [0.28, 0.52, FLOOR_Z + 0.03])  # placed/0
    tray.add_released(solid_points(0.05, 0.05, 0.05) + [0.40, 0.64, FLOOR_Z + 0.03])  # placed/1
    # the look sees placed/0 where it was (a little lower), placed/1 is gone, and a new object
    seen = np.vstack([floor_points(), box_points(0.28, 0.52, 0.05, 0.05, 0.045),
                      box_points(0.40, 0.50, 0.04, 0.04, 0.03)])
    gone = tray.update_from_look(seen)
    assert gone == ["placed/1"]
    assert set(tray.objects) == {"placed/0", "placed/2"}
    assert tray.objects["placed/0"].tops[:, 2].max() == pytest.approx(FLOOR_Z + 0.045, abs=CELL_M)
    assert np.allclose(tray.objects["placed/2"].box(FLOOR_Z).center[:2], [0.40, 0.50], atol=0.005)


def test_a_look_that_does_not_see_an_object_keeps_it():
    tray = contents()
    tray.add_released(solid_points(0.05, 0.05, 0.05) + [0.40, 0.64, FLOOR_Z + 0.03])
    half_floor = floor_points()[floor_points()[:, 0] < 0.34]  # the camera saw only x < 0.34
    assert tray.update_from_look(half_floor) == []
    assert set(tray.objects) == {"placed/0"}


def test_the_heights_of_the_contents_on_a_coarser_grid():
    tray = contents()
    tray.add_released(solid_points(0.05, 0.05, 0.05) + [0.34, 0.58, FLOOR_Z + 0.03])
    grid = tray.geometry.grid(0.01)
    h = tray.heights(grid)
    ij = grid.index(np.array([[0.34, 0.58], [0.25, 0.50]]))
    assert h[ij[0, 0], ij[0, 1]] == pytest.approx(0.05, abs=CELL_M)
    assert h[ij[1, 0], ij[1, 1]] == 0.0


def _turned_grid(cell_m=0.005):
    """A grid over a tray turned 30 deg about the vertical (no walls)."""
    a = np.radians(30.0)
    axes = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    return TrayGeometry(np.array([0.34, 0.58]), axes, np.array([0.14, 0.12]), FLOOR_Z).grid(cell_m)


def _frame_like(seed=0, n=60000) -> np.ndarray:
    """A camera frame's worth of points, the tray a part of them, rows of NaN and stray infs."""
    rng = np.random.default_rng(seed)
    pts = np.c_[rng.uniform(0.0, 0.7, n), rng.uniform(0.2, 1.0, n), rng.uniform(0.19, 0.3, n)]
    pts[rng.random(n) < 0.1] = np.nan
    pts[rng.integers(0, n, 50), rng.integers(0, 3, 50)] = np.inf
    return pts.astype(np.float32)


def test_cells_of_returns_what_indexing_every_finite_point_returns():
    grid = _turned_grid()
    for frame in (_frame_like(0), _frame_like(1).astype(float)):
        pts = np.asarray(frame, float)
        pts = pts[np.all(np.isfinite(pts), axis=1)]
        uv = (pts[:, :2] - grid.geometry.center_xy) @ grid.geometry.axes + grid.geometry.half_m
        ij = np.floor(uv / grid.cell_m).astype(np.int64)  # the rotation as one matrix product
        ok = grid.inside(ij)
        np.testing.assert_array_equal(grid.index(pts[:, :2]), ij)
        got_pts, got_ij = grid.cells_of(frame)
        np.testing.assert_array_equal(got_pts, pts[ok])
        np.testing.assert_array_equal(got_ij, ij[ok])
        expected = np.full(grid.shape, -np.inf)
        np.maximum.at(expected, (ij[ok, 0], ij[ok, 1]), pts[ok, 2] - FLOOR_Z)
        expected[np.isinf(expected)] = np.nan
        np.testing.assert_array_equal(grid.heights(frame), expected)
    assert 0 < len(got_pts) < len(pts)


def test_cells_of_nothing():
    pts, ij = _turned_grid().cells_of(np.zeros((0, 3)))
    assert pts.shape == (0, 3) and ij.shape == (0, 2)
    assert np.isnan(_turned_grid().heights(np.full((4, 3), np.nan))).all()


def _cells_by_numpy(grid, points):
    """The numpy formulation of ``cells_of``: the bounding box on x/y, a finite z, then
    :meth:`index` and :meth:`inside`."""
    pts = np.asarray(points).reshape(-1, 3)
    lo, hi = grid._bounds_xy()
    x, y = pts[:, 0], pts[:, 1]
    near = (x >= lo[0]) & (x <= hi[0]) & (y >= lo[1]) & (y <= hi[1]) & np.isfinite(pts[:, 2])
    pts = np.asarray(pts[near], float)
    ij = grid.index(pts[:, :2])
    ok = grid.inside(ij)
    return pts[ok], ij[ok]


def test_cells_of_points_on_cell_edges_and_on_the_bounds():
    grid = _turned_grid()
    g = grid.geometry
    corners = grid.centres().reshape(-1, 2) + 0.5 * grid.cell_m * (g.axes[:, 0] + g.axes[:, 1])
    lo, hi = grid._bounds_xy()
    edges = np.r_[corners, np.nextafter(corners, 0.0), [lo, hi, [lo[0], hi[1]], [hi[0], lo[1]]]]
    pts = np.c_[edges, np.full(len(edges), FLOOR_Z + 0.01)]
    for frame in (pts, pts.astype(np.float32)):
        got, expected = grid.cells_of(frame), _cells_by_numpy(grid, frame)
        for a, b in zip(got, expected):
            np.testing.assert_array_equal(a, b)
        assert got[0].dtype == np.float64 and got[1].dtype == np.int64


def test_the_core_pass_refuses_bad_arguments_by_name():
    from grasp_pipeline import _core

    pts, eye = np.zeros((3, 3)), np.eye(2)
    good = dict(center=[0.3, 0.5], axes=eye, half=[0.1, 0.1], cell_m=0.01, nu=20, nv=20,
                lo=[0.1, 0.3], hi=[0.5, 0.7])
    cases = [(dict(points=pts[:, :2].copy()), ValueError, "points: expected shape (n, 3)"),
             (dict(points=pts.astype(np.int64)), TypeError, "points: expected dtype float64"),
             (dict(points=pts, center=[np.nan, 0.0]), ValueError, "center: expected two finite"),
             (dict(points=pts, axes=np.eye(3)), ValueError, "axes: expected shape (2, 2)"),
             (dict(points=pts, cell_m=0.0), ValueError, "cell_m must be a positive")]
    for args, exc, text in cases:
        with pytest.raises(exc, match=re.escape(text)):
            _core.points_in_grid_cells(**{**good, **args})
