"""Objects modelled by their points (motion/object_points.py) and the perceived scene's choice
between points and boxes (PerceivedScene.object_tops)."""

import numpy as np
import pytest

from grasp_pipeline.motion.exceptions import EnvironmentCloudError
from grasp_pipeline.motion.object_points import (ObjectPoints, PointModel, column_tops, columns,
                                                 footprint_cells, footprint_overlap, seen_cells,
                                                 seen_cells_among, seen_fraction, seen_through)
from grasp_pipeline.motion.occupancy import OrientedBox, cell_rounding_m
from grasp_pipeline.motion.perceived_scene import PerceivedScene

CELL = 0.005
TABLE_Z = 0.2
MODEL = PointModel(CELL, 0.5, 0.8, 0.5)


def _cylinder(cx, cy, r, h, n=4000, seed=0):
    """Points on the top disc and the side of an upright cylinder standing on the table."""
    rng = np.random.default_rng(seed)
    a, rr = rng.uniform(0, 2 * np.pi, n), r * np.sqrt(rng.uniform(0, 1, n))
    top = np.c_[cx + rr * np.cos(a), cy + rr * np.sin(a), np.full(n, TABLE_Z + h)]
    b, z = rng.uniform(0, 2 * np.pi, n), rng.uniform(TABLE_Z, TABLE_Z + h, n)
    side = np.c_[cx + r * np.cos(b), cy + r * np.sin(b), z]
    return np.vstack([top, side])


def _table(x0, x1, y0, y1, step=0.003):
    X, Y = np.meshgrid(np.arange(x0, x1, step), np.arange(y0, y1, step))
    return np.c_[X.ravel(), Y.ravel(), np.full(X.size, TABLE_Z)]


def _box(cx, cy, ex, ey, h, yaw=0.0):
    c, s = np.cos(yaw), np.sin(yaw)
    R = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    return OrientedBox(np.array([cx, cy, TABLE_Z + h / 2]), R, np.array([ex, ey, h]))


def test_column_tops_keep_the_highest_cell_of_each_column():
    pts = _cylinder(0.5, 0.0, 0.03, 0.1025)
    tops = column_tops(pts, CELL)
    ij = np.floor(tops[:, :2] / CELL).astype(int)
    assert len(np.unique(ij, axis=0)) == len(tops)  # one per column
    top_cell = (np.floor((TABLE_Z + 0.1025) / CELL) + 0.5) * CELL
    assert tops[:, 2].max() == pytest.approx(top_cell)
    assert np.mean(np.isclose(tops[:, 2], top_cell)) > 0.9  # rim columns may hold side points only
    area = len(tops) * CELL ** 2
    assert np.pi * 0.03 ** 2 < area < np.pi * 0.036 ** 2  # the disc, rounded up to whole cells
    assert column_tops(np.zeros((0, 3)), CELL).shape == (0, 3)


def test_columns_reach_down_to_the_table_plane():
    top = np.array([[0.5025, 0.0025, TABLE_Z + 0.0525]])
    col = columns(top, np.array([0.0, 0.0, 1.0]), -TABLE_Z, CELL)
    assert len(col) == 11 and np.allclose(col[:, :2], top[:, :2])
    assert col[:, 2].max() == pytest.approx(top[0, 2]) and col[:, 2].min() < TABLE_Z + CELL
    assert np.allclose(np.diff(np.sort(col[:, 2])), CELL)


def test_a_cylinder_covers_about_pi_over_four_of_its_square_box():
    tops = column_tops(_cylinder(0.5, 0.0, 0.03, 0.1), CELL)
    frac = seen_fraction(tops, _box(0.5, 0.0, 0.06, 0.06, 0.1), CELL)
    assert 0.75 <= frac <= 1.0
    half = tops[tops[:, 0] < 0.5]
    assert seen_fraction(half, _box(0.5, 0.0, 0.06, 0.06, 0.1), CELL) < 0.6


def test_footprints_of_rotated_boxes_and_their_overlap():
    a = _box(0.5, 0.0, 0.05, 0.10, 0.1)
    n = len(footprint_cells(a, CELL))
    assert abs(n - 0.05 * 0.10 / CELL ** 2) <= 0.1 * n
    turned = _box(0.5, 0.0, 0.05, 0.10, 0.1, yaw=np.pi / 2)
    assert abs(len(footprint_cells(turned, CELL)) - n) <= 0.1 * n
    assert footprint_overlap(a, a, CELL) == 1.0
    assert footprint_overlap(a, _box(0.7, 0.0, 0.05, 0.10, 0.1), CELL) == 0.0
    assert 0.4 < footprint_overlap(a, turned, CELL) < 0.6  # a cross: the 5 x 5 cm middle


def test_seen_through_counts_the_footprint_cells_holding_any_point():
    box = _box(0.5, 0.0, 0.05, 0.05, 0.1)
    cells = seen_cells(_table(0.4, 0.6, -0.1, 0.1), CELL)
    assert seen_through(box, cells, CELL) == pytest.approx(1.0)
    shadow = seen_cells(_table(0.4, 0.5, -0.1, 0.1), CELL)  # nothing seen beyond x = 0.5
    assert 0.4 < seen_through(box, shadow, CELL) < 0.6


def test_seen_cells_among_are_the_seen_cells_of_the_candidates():
    rng = np.random.default_rng(3)
    env = rng.uniform([0.2, -0.3, 0.1], [0.8, 0.3, 0.4], (20000, 3)).astype(np.float32)
    env[::97, 0] = np.nan
    env[::89, 2] = np.inf  # a row is kept only when all three coordinates are finite
    env[::83, 1] = -np.inf
    obj = rng.uniform([0.45, -0.05, 0.2], [0.55, 0.05, 0.3], (500, 3))
    boxes = [_box(0.5, 0.0, 0.05, 0.05, 0.1), _box(0.3, 0.2, 0.04, 0.08, 0.1, yaw=0.6),
             _box(0.85, 0.35, 0.1, 0.1, 0.1)]  # (partly beyond the points)
    needed = np.concatenate([footprint_cells(b, CELL) for b in boxes])
    among = seen_cells_among([env, obj], needed, CELL)
    every = seen_cells(np.vstack([env, obj]), CELL)
    assert np.array_equal(among, np.intersect1d(needed, every))
    for b in boxes:
        assert seen_through(b, among, CELL) == seen_through(b, every, CELL)
    assert len(seen_cells_among([env], np.zeros(0, np.int64), CELL)) == 0
    assert len(seen_cells_among([np.zeros((0, 3))], needed, CELL)) == 0


def test_object_points_distance_is_a_lower_bound_of_the_cells():
    pts = np.array([[0.5025, 0.0025, 0.2525]])
    op = ObjectPoints(pts, CELL, pad_m=0.1)
    q = np.array([[0.5525, 0.0025, 0.2525], [0.8, 0.0, 0.25]])
    d = op.distance_m(q)
    assert d[0] == pytest.approx(0.05 - cell_rounding_m(CELL)) and np.isinf(d[1])
    assert np.all(np.isinf(ObjectPoints(np.zeros((0, 3)), CELL, 0.1).distance_m(q)))
    with pytest.raises(EnvironmentCloudError):
        ObjectPoints(np.array([[np.nan, 0.0, 0.0]]), CELL, 0.1)
    arrays = op.core_arrays()
    assert np.allclose(arrays["center_m"], pts[0]) and arrays["fine_m"] == pytest.approx(cell_rounding_m(CELL))


def _scene(boxes, points, env):
    return PerceivedScene(env, boxes, list(range(len(boxes))), object_points=points)


def test_the_scene_models_a_seen_object_by_its_points_and_an_unseen_one_by_its_box():
    bottle = _box(0.5, 0.0, 0.06, 0.06, 0.1)
    hidden = _box(0.6, 0.0, 0.05, 0.05, 0.1)
    env = _table(0.4, 0.55, -0.1, 0.1)  # nothing seen beyond x = 0.55: the hidden one's shadow
    tops = _scene([bottle, hidden], [_cylinder(0.5, 0.0, 0.03, 0.1), np.zeros((0, 3))], env).object_tops(MODEL)
    assert len(tops[0]) > 100 and tops[1] is None
    boxes, top_pts = _scene([bottle, hidden], [_cylinder(0.5, 0.0, 0.03, 0.1), np.zeros((0, 3))],
                            env).obstacles(0, MODEL)
    assert boxes == [hidden] and len(top_pts) == 0  # the target is no obstacle
    only_boxes = PointModel(CELL, 1.5, 0.8, 0.5)
    assert _scene([bottle], [_cylinder(0.5, 0.0, 0.03, 0.1)], env).object_tops(only_boxes) == [None]


def test_an_unseen_track_where_the_table_is_seen_or_that_doubles_a_seen_object_is_no_obstacle():
    bottle = _box(0.5, 0.0, 0.06, 0.06, 0.1)
    moved_away = _box(0.45, 0.05, 0.04, 0.04, 0.1)
    double = _box(0.505, 0.0, 0.07, 0.09, 0.1)  # a second track of the bottle, reaching behind it
    env = _table(0.4, 0.6, -0.1, 0.1)
    scene = _scene([bottle, moved_away, double], [_cylinder(0.5, 0.0, 0.03, 0.1), np.zeros((0, 3)),
                                                  np.zeros((0, 3))], env)
    tops = scene.object_tops(MODEL)
    assert len(tops[0]) > 100 and len(tops[1]) == 0 and len(tops[2]) == 0
    boxes, pts = scene.obstacles(1, MODEL)
    assert boxes == [] and len(pts) == len(tops[0])
