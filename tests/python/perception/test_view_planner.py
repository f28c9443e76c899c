"""Next views of an object's sides (perception/view_planner.py), on synthetic views."""

import numpy as np

from grasp_pipeline import _core
from grasp_pipeline.perception.scene_volume import CameraModel, SceneVolume
from grasp_pipeline.perception.side_coverage import side_coverage
from grasp_pipeline.perception.view_planner import candidate_views, rank_views
from grasp_pipeline.perception.volume_config import VolumeConfig

from .synthetic_depth import HEIGHT_PX, K, WIDTH_PX, look_at, render

TABLE = _core.Plane([0.0, 0.0, 1.0], -0.2)
CUBE = ((0.45, -0.05, 0.20), (0.55, 0.05, 0.30))
CENTRE = np.array([0.5, 0.0, 0.25])
FRONT = look_at((0.2, 0.0, 0.45), CENTRE)


def test_candidates_look_at_the_target_upright_from_the_configured_sphere():
    cfg = VolumeConfig()
    views = candidate_views(CENTRE, cfg)
    assert len(views) == 12 * 3 * 2
    for v in views:
        T = v.T_world_camera
        eye = T[:3, 3]
        to_target = (CENTRE - eye) / np.linalg.norm(CENTRE - eye)
        assert np.allclose(T[:3, 2], to_target)
        assert abs(T[2, 0]) < 1e-12 and T[2, 1] < 0  # image x horizontal, image down is down
        assert np.isclose(np.linalg.det(T[:3, :3]), 1.0)
        assert np.isclose(np.linalg.norm(eye - CENTRE), v.distance_m)
        assert np.isclose(np.degrees(np.arcsin((eye - CENTRE)[2] / v.distance_m)), v.elevation_deg)
    assert {v.azimuth_deg for v in views} == set(np.arange(0.0, 360.0, 30.0))


def _unknown_far_side(boxes):
    vol = SceneVolume()
    vol.integrate(render(FRONT, boxes, 0.2), K, FRONT)
    cov = side_coverage(vol, CENTRE, np.eye(3), (0.1, 0.1, 0.1), TABLE, 0.03, 0.015)
    return vol, cov


def test_the_best_views_of_a_far_side_stand_on_that_side():
    vol, cov = _unknown_far_side((CUBE,))
    ranked = rank_views(vol, cov.unknown_points, CENTRE, VolumeConfig(), reference_position=FRONT[:3, 3])
    assert ranked and ranked[0].seen_fraction > 0.8
    best_az = ranked[0].azimuth_deg
    assert min(best_az, 360 - best_az) <= 60  # behind the cube (+x)
    seen = [v.seen for v in ranked]
    assert seen == sorted(seen, reverse=True)
    from_front = [v for v in ranked if v.azimuth_deg == 180.0]
    assert all(v.seen_fraction < 0.2 for v in from_front)


def test_an_occupied_wall_hides_the_far_side_from_the_views_behind_it():
    wall = ((0.62, -0.15, 0.20), (0.64, 0.15, 0.45))
    camera = CameraModel(K, WIDTH_PX, HEIGHT_PX)
    behind = look_at(CENTRE + 0.4 * np.array([np.cos(np.radians(20)), 0, np.sin(np.radians(20))]), CENTRE)
    vol, cov = _unknown_far_side((CUBE,))
    open_view = int(vol.visible(cov.unknown_points, behind, 0.1, camera).sum())
    vol, cov = _unknown_far_side((CUBE, wall))  # the wall's upper part is seen (occupied)
    walled = int(vol.visible(cov.unknown_points, behind, 0.1, camera).sum())
    assert open_view > 1000 and walled < 0.5 * open_view
    ranked = rank_views(vol, cov.unknown_points, CENTRE, VolumeConfig(), camera=camera)
    best = ranked[0]  # over the wall or around its end, not straight through it
    assert best.elevation_deg == 60.0 or best.azimuth_deg not in (0.0, 30.0, 330.0)


def test_nothing_unknown_nothing_to_rank():
    vol = SceneVolume()
    assert rank_views(vol, np.zeros((0, 3)), CENTRE, VolumeConfig()) == []
