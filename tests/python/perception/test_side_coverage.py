"""How well an object's sides are known (perception/side_coverage.py), on synthetic views."""

import numpy as np

from grasp_pipeline import _core
from grasp_pipeline.perception.scene_volume import UNKNOWN, SceneVolume
from grasp_pipeline.perception.side_coverage import FACES, shell_mask, side_coverage

from .synthetic_depth import K, look_at, render

TABLE = _core.Plane([0.0, 0.0, 1.0], -0.2)
CUBE = ((0.45, -0.05, 0.20), (0.55, 0.05, 0.30))
CENTRE, EXTENTS = (0.5, 0.0, 0.25), (0.1, 0.1, 0.1)
FRONT = look_at((0.2, 0.0, 0.45), CENTRE)   # from -x, 40 deg above the table
BACK = look_at((0.8, 0.0, 0.45), CENTRE)    # from +x


def _seen(*views, boxes=(CUBE,)):
    vol = SceneVolume()
    for T in views:
        vol.integrate(render(T, boxes, 0.2), K, T)
    return vol


def _coverage(vol, neighbours=()):
    return side_coverage(vol, CENTRE, np.eye(3), EXTENTS, TABLE, 0.03, 0.015, neighbours)


def test_the_far_face_of_a_cube_seen_from_one_side_is_unknown():
    cov = _coverage(_seen(FRONT))
    far, near = cov.unknown_fraction[FACES.index("+x")], cov.unknown_fraction[FACES.index("-x")]
    assert far > 0.5 and near < 0.05
    assert cov.worst == far and 0 < cov.overall < far
    assert all(v > 0 for v in cov.voxels)
    assert np.all(cov.unknown_points[:, 2] >= 0.215 - 1e-9)  # none below the table clearance
    assert np.all(_seen(FRONT).classify(cov.unknown_points) == UNKNOWN)


def test_a_view_from_the_other_side_fills_it_in():
    cov = _coverage(_seen(FRONT, BACK))
    assert cov.unknown_fraction[FACES.index("+x")] < 0.05


def test_a_neighbours_box_is_not_part_of_the_shell():
    neighbour = ((0.56, -0.05, 0.20), (0.60, 0.05, 0.26))  # against the far face
    vol = _seen(FRONT, boxes=(CUBE, neighbour))
    box = ((0.58, 0.0, 0.23), np.eye(3), (0.04, 0.1, 0.06))
    alone, without = _coverage(vol), _coverage(vol, [box])
    k = FACES.index("+x")
    assert without.voxels[k] < alone.voxels[k]
    assert without.voxels[FACES.index("-x")] == alone.voxels[FACES.index("-x")]


def test_shell_faces_split_the_corners_along_the_diagonals():
    local = np.array([[0.06, 0.0, 0], [0.0, 0.06, 0], [-0.06, 0.01, 0], [0.01, -0.06, 0],
                      [0.07, 0.06, 0], [0.0, 0.0, 0], [0.10, 0.0, 0]])
    inside, face = shell_mask(local, np.array([0.05, 0.05]), 0.03)
    assert inside.tolist() == [True, True, True, True, True, False, False]
    assert face[:5].tolist() == [0, 1, 2, 3, 0]
