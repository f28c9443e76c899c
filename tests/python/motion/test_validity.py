"""The validator keeps its collision scene while the obstacles stay the same objects, and its
verdicts are those of a validator given a freshly built scene."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from grasp_pipeline.motion import core_checker
from grasp_pipeline.motion.object_points import column_tops
from grasp_pipeline.motion.occupancy import OrientedBox
from grasp_pipeline.robot import description as rm


def _scene(rng, table_cloud):
    boxes = [OrientedBox(np.array([0.55, 0.0, 0.25]), np.eye(3), np.array([0.05, 0.06, 0.1])),
             OrientedBox(np.array([0.55, 0.09, 0.26]), np.eye(3), np.array([0.06, 0.06, 0.12])),
             OrientedBox(np.array([0.45, -0.12, 0.24]), np.eye(3), np.array([0.04, 0.04, 0.08]))]
    a, r = rng.uniform(0, 2 * np.pi, 2000), 0.03 * np.sqrt(rng.uniform(0, 1, 2000))
    cap = np.c_[0.55 + r * np.cos(a), 0.09 + r * np.sin(a), np.full(2000, 0.32)]
    tops = [None, column_tops(cap, 0.005), None]
    plane = SimpleNamespace(n=np.array([0.0, 0.0, 1.0]), c=-0.2)
    return table_cloud(rng, n=30000), boxes, tops, plane


def _fresh_verdicts(planner, Q: np.ndarray) -> np.ndarray:
    """Verdicts of the planner's validator with its scene rebuilt from scratch."""
    v = planner.validator
    fresh = core_checker.collision_scene(v.config, v.env, v.boxes, v._env_cleared, v.points)
    checker = planner.validator.core()
    checker.set_scene(fresh)
    try:
        return checker.check_batch(Q)
    finally:
        checker.set_scene(v._scene)


def test_set_target_keeps_the_scene_of_the_same_obstacles(planner, table_cloud, rng):
    env, boxes, tops, plane = _scene(rng, table_cloud)
    planner.set_scene(env, boxes, target_index=0, object_tops=tops, plane=plane)
    v = planner.validator
    scene, points, cleared = v._scene, v.points, v._env_cleared
    planner.set_target(0)
    assert v._scene is scene and v.points is points and v._env_cleared is cleared
    planner.set_objects(boxes, [None, tops[1].copy(), None], target_index=0)  # equal tops: kept
    assert v._scene is scene and v.points is points
    planner.set_target(2)  # another target: another cleared region, another scene
    assert v._scene is not scene and v._env_cleared is not cleared
    planner.set_target(0)  # back: the map's view of that region is reused, the scene rebuilt
    assert v._env_cleared is cleared
    moved = [None, tops[1] + np.array([0.0, 0.0, 0.005]), None]
    planner.set_objects(boxes, moved, target_index=0)
    assert v.points is not points and not np.array_equal(v.points.points, points.points)


def test_verdicts_equal_those_of_a_fresh_scene(planner, table_cloud, rng):
    env, boxes, tops, plane = _scene(rng, table_cloud)
    planner.set_scene(env, boxes, target_index=0, object_tops=tops, plane=plane)
    T = planner.ik.fk_tcp(rm.READY_Q)
    T[:3, 3] = [0.55, 0.02, 0.30]
    q_t = planner.ik.solve_tcp(T, rm.READY_Q).q
    v = planner.validator
    for target in (0, None, 2, 0, 0):
        planner.set_target(target)
        for allow in (False, True):
            v.allow_target_contact = allow
            Q = np.vstack([rng.uniform(v.q_min, v.q_max, size=(400, 7)),
                           q_t + rng.normal(0.0, 0.05, size=(600, 7))])
            ok = v.check_batch(Q)
            assert np.array_equal(ok, _fresh_verdicts(planner, Q))
            assert np.array_equal(ok, v._python_check_batch(Q))
            assert 0 < ok.sum() < len(Q)
    v.allow_target_contact = False


def test_attached_object_rebuilds_the_point_obstacles_with_their_reach(planner, table_cloud, rng):
    env, boxes, tops, plane = _scene(rng, table_cloud)
    planner.set_scene(env, boxes, target_index=0, object_tops=tops, plane=plane)
    before = planner.validator.points
    planner.robot.attach("held", np.array([[0.0, 0.0, 0.1]]), np.array([0.2]))  # a big sphere
    try:
        planner.validator.core()  # the validator takes the new spheres (and their reach)
        planner.set_target(0)
        after = planner.validator.points
        assert after is not before and after.pad_m > before.pad_m
        assert np.array_equal(after.points, before.points)
    finally:
        planner.robot.detach()
        planner.set_target(None)
