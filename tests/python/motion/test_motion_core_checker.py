"""The C++ state checker (``_core.StateChecker``) against the numpy reference validator:
same forward kinematics as MuJoCo, identical validity on random and near-boundary states,
identical segment answers, and clear errors for bad input."""

import mujoco
import numpy as np
import pytest

from grasp_pipeline import _core
from grasp_pipeline.motion import core_checker
from grasp_pipeline.motion.occupancy import OrientedBox
from grasp_pipeline.robot import description as rm

BISECTION_STEPS = 30


def _scene(planner, table_cloud, rng):
    """Table at z = 0.2 m, three boxes on it; box 0 is the target (cleared for the hand)."""
    boxes = [OrientedBox(np.array([0.55, 0.0, 0.25]), np.eye(3), np.array([0.05, 0.06, 0.1])),
             OrientedBox(np.array([0.5, 0.25, 0.24]), np.eye(3), np.array([0.06, 0.04, 0.08])),
             OrientedBox(np.array([0.45, -0.25, 0.26]),
                         np.array([[0.8, -0.6, 0.0], [0.6, 0.8, 0.0], [0.0, 0.0, 1.0]]),
                         np.array([0.05, 0.05, 0.12]))]
    planner.set_scene(table_cloud(rng, n=40000), boxes, target_index=0)
    return planner.validator


def _near_boundary(v, rng, n_pairs):
    """States within ~1e-9 of a validity change (bisection on random valid/invalid pairs,
    by the reference), plus jitter of 1e-7 .. 1e-3 rad around them."""
    Q = rng.uniform(v.q_min, v.q_max, size=(8 * n_pairs, 7))
    ok = v._python_check_batch(Q)
    good, bad = Q[ok][:n_pairs], Q[~ok][:n_pairs]
    m = min(len(good), len(bad))
    a, b = good[:m], bad[:m]
    lo, hi = np.zeros(m), np.ones(m)
    for _ in range(BISECTION_STEPS):
        mid = 0.5 * (lo + hi)
        valid = v._python_check_batch(a + (b - a) * mid[:, None])
        lo, hi = np.where(valid, mid, lo), np.where(valid, hi, mid)
    edge = np.vstack([a + (b - a) * lo[:, None], a + (b - a) * hi[:, None]])
    jitter = [edge + rng.normal(0.0, s, edge.shape) for s in (1e-7, 1e-5, 1e-3)]
    return np.clip(np.vstack([edge] + jitter), v.q_min, v.q_max)


def _compare(v, Q):
    core = v.check_batch(Q)
    ref = v._python_check_batch(Q)
    bad = np.nonzero(core != ref)[0]
    assert len(bad) == 0, f"{len(bad)} of {len(Q)} differ, e.g. q={Q[bad[0]].tolist()}: {v.explain(Q[bad[0]])}"
    return ref


def test_core_fk_equals_mujoco(planner, rng):
    rs, m = planner.robot, planner.model
    model = core_checker.robot_model(rs, planner.validator.q_min, planner.validator.q_max)
    d = mujoco.MjData(m)
    for q in rng.uniform(rm.PANDA_Q_MIN, rm.PANDA_Q_MAX, size=(100, 7)):
        d.qpos[:] = rs.fixed_qpos
        d.qpos[rs.arm_idx] = q
        mujoco.mj_kinematics(m, d)
        R, p = model.body_poses(q)
        assert np.abs(R - d.xmat.reshape(-1, 3, 3)).max() <= 1e-9
        assert np.abs(p - d.xpos).max() <= 1e-9
        assert np.abs(planner.validator.core().sphere_centres(q) - rs.centres(q[None])[0]).max() <= 1e-9


def test_core_equals_reference_on_random_and_boundary_states(planner, table_cloud, rng):
    """≥ 10 000 states over three scenes (map + boxes; target contact allowed; free space)."""
    v = _scene(planner, table_cloud, rng)
    total, valid = 0, 0
    try:
        for allow in (False, True):
            v.allow_target_contact = allow
            Q = np.vstack([rng.uniform(v.q_min, v.q_max, size=(2500, 7)), _near_boundary(v, rng, 150)])
            if allow:  # hand states around the target (its cleared region matters there)
                T = planner.ik.fk_tcp(rm.READY_Q)
                T[:3, 3] = [0.55, 0.0, 0.27]
                q_t = planner.ik.solve_tcp(T, rm.READY_Q).q
                Q = np.vstack([Q, q_t + rng.normal(0.0, 0.05, size=(1500, 7))])
            valid += int(_compare(v, Q).sum())
            total += len(Q)
    finally:
        v.allow_target_contact = False
    v.set_scene(None, [])
    Q = np.vstack([rng.uniform(v.q_min, v.q_max, size=(1500, 7)), _near_boundary(v, rng, 100)])
    valid += int(_compare(v, Q).sum())
    total += len(Q)
    assert total >= 10_000 and 0.2 * total < valid < 0.9 * total


def _self_boundary(v, rng, n_pairs):
    """States within ~1e-9 of a self-collision change (bisection on the reference's smallest
    self clearance between random self-free and self-colliding states), plus jitter."""
    Q = rng.uniform(v.q_min, v.q_max, size=(10 * n_pairs, 7))
    margin = v.config.self_collision_margin_m
    free = v._components(Q)[1] >= margin
    a, b = Q[free][:n_pairs], Q[~free][:n_pairs]
    m = min(len(a), len(b))
    a, b = a[:m], b[:m]
    lo, hi = np.zeros(m), np.ones(m)
    for _ in range(BISECTION_STEPS):
        mid = 0.5 * (lo + hi)
        ok = v._components(a + (b - a) * mid[:, None])[1] >= margin
        lo, hi = np.where(ok, mid, lo), np.where(ok, hi, mid)
    edge = np.vstack([a + (b - a) * lo[:, None], a + (b - a) * hi[:, None]])
    jitter = [edge + rng.normal(0.0, s, edge.shape) for s in (1e-8, 1e-6, 1e-4)]
    return np.clip(np.vstack([edge] + jitter), v.q_min, v.q_max)


def test_core_equals_reference_at_self_collision_boundaries(planner, table_cloud, rng):
    """Self-collision decided ahead of time (link pairs proven clear, joint-space tables of
    the hand against the forearm) and by the sphere trees: identical to the reference on
    states at the self-collision boundary, including hand states turning about the last two
    joints, in free space and in the table scene."""
    for scene in ("free", "table"):
        if scene == "free":
            planner.set_scene(np.zeros((0, 3)))
        v = planner.validator if scene == "free" else _scene(planner, table_cloud, rng)
        Q = _self_boundary(v, rng, 200)
        wrist = np.repeat(rng.uniform(v.q_min, v.q_max, size=(40, 7)), 50, axis=0)
        wrist[:, 5:] = rng.uniform(v.q_min[5:], v.q_max[5:], size=(len(wrist), 2))  # hand vs forearm
        ref_self = v._components(Q)[1] >= v.config.self_collision_margin_m
        assert 0.2 * len(Q) < ref_self.sum() < 0.8 * len(Q)
        _compare(v, np.vstack([Q, wrist]))


def test_core_segments_equal_reference(planner, table_cloud, rng):
    v = _scene(planner, table_cloud, rng)
    step = planner.config.planner_check_step_rad
    for _ in range(60):
        qa, qb = rng.uniform(v.q_min, v.q_max, size=(2, 7))
        qb = qa + 0.3 * (qb - qa)
        for start in (False, True):
            ref = bool(np.all(v._python_check_batch(v.segment_states(qa, qb, step, start))))
            assert v.check_segment(qa, qb, step, start) == ref


def test_finger_opening_rebuilds_the_checker(planner, rng):
    planner.set_scene(np.zeros((0, 3)))
    v = planner.validator
    Q = rng.uniform(v.q_min, v.q_max, size=(2000, 7))
    try:
        planner.set_finger_opening(0.0)
        assert np.array_equal(v.check_batch(Q), v._python_check_batch(Q))
        assert np.abs(v.core().sphere_centres(Q[0]) - planner.robot.centres(Q[:1])[0]).max() <= 1e-9
    finally:
        planner.set_finger_opening(rm.GRIPPER_MAX_WIDTH_M)


def test_validator_non_finite_rows_are_invalid(planner):
    planner.set_scene(np.zeros((0, 3)))
    v = planner.validator
    Q = np.array([rm.READY_Q, rm.READY_Q], dtype=float)
    Q[1, 2] = np.nan
    assert v.check_batch(Q).tolist() == [True, False]
    assert not v.is_valid(Q[1])
    assert not v.check_segment(Q[0], Q[1], 0.01)


def test_checker_bad_input(planner):
    core = planner.validator.core()
    with pytest.raises(ValueError, match=r"q: expected shape \(7,\)"):
        core.check(np.zeros(6))
    with pytest.raises(ValueError, match="finite"):
        core.check(np.full(7, np.nan))
    with pytest.raises(TypeError, match="q: expected"):
        core.check("abcdefg")
    with pytest.raises(ValueError, match=r"Q: expected shape \(N, 7\)"):
        core.check_batch(np.zeros((3, 6)))
    with pytest.raises(TypeError, match="real numbers"):
        core.check_batch(np.zeros((3, 7), dtype=object))
    with pytest.raises(ValueError, match="max_step_rad"):
        core.check_segment(np.zeros(7), np.ones(7), 0.0)
    with pytest.raises(ValueError, match="max_step_rad"):
        core.check_segment(np.zeros(7), np.ones(7), float("nan"))
    with pytest.raises(TypeError):
        core.check_ompl_state(object())
    assert core.check_batch(np.zeros((0, 7))).shape == (0,)


def test_model_and_scene_bad_input(planner):
    v = planner.validator
    arrays = core_checker._body_rows(planner.robot)
    with pytest.raises(ValueError, match="missing entry"):
        _core.RobotCollisionModel(arrays)
    with pytest.raises(ValueError, match="field_m"):
        _core.CollisionScene(0.005, 0.0, has_env=True, field_m=np.full((2, 2, 2), np.nan, np.float32),
                             origin_m=np.zeros(3), voxel_size_m=0.01)
    with pytest.raises(ValueError, match="voxel_size_m"):
        _core.CollisionScene(0.005, 0.0, has_env=True, field_m=np.zeros((2, 2, 2), np.float32),
                             origin_m=np.zeros(3), voxel_size_m=0.0)
    with pytest.raises(ValueError, match="negative extents"):
        _core.CollisionScene(0.005, 0.0, box_centers_m=np.zeros((1, 3)), box_rotations=np.eye(3)[None],
                             box_extents_m=-np.ones((1, 3)))
    with pytest.raises(ValueError, match=r"box_rotations: expected shape"):
        _core.CollisionScene(0.005, 0.0, box_centers_m=np.zeros((2, 3)), box_rotations=np.eye(3)[None],
                             box_extents_m=np.ones((2, 3)))
    with pytest.raises(ValueError, match="collision_margin_m"):
        _core.CollisionScene(float("inf"), 0.0)
    model = core_checker.robot_model(planner.robot, v.q_min, v.q_max)
    assert model.num_spheres == len(planner.robot.spheres.radius)


def test_first_invalid_state_is_the_first_invalid_dense_state(planner, table_cloud, rng):
    """One C++ call over a whole polyline = the first False of the reference validator over
    the concatenated dense segments (in path order), on paths through the table scene."""
    v = _scene(planner, table_cloud, rng)
    step = planner.config.final_check_step_rad
    found = 0
    for _ in range(40):
        wp = rng.uniform(v.q_min, v.q_max, size=(4, 7))
        wp[1:] = wp[0] + 0.25 * (wp[1:] - wp[0])
        dense = [v.segment_states(a, b, step) for a, b in zip(wp[:-1], wp[1:])]
        ok = v._python_check_batch(np.vstack(dense))
        got = v.first_invalid_state(wp, step)
        if np.all(ok):
            assert got is None
            continue
        found += 1
        first = int(np.argmin(ok))
        seg = int(np.searchsorted(np.cumsum([len(d) for d in dense]), first, side="right"))
        assert got is not None and got[0] == seg
        assert np.array_equal(got[1], np.vstack(dense)[first])
    assert found >= 5
    with pytest.raises(ValueError, match=r"waypoints: expected shape \(N, 7\)"):
        v.core().first_invalid_on_path(np.zeros((3, 6)), step)
    with pytest.raises(ValueError, match="max_step_rad"):
        v.core().first_invalid_on_path(np.zeros((3, 7)), 0.0)
    assert v.core().first_invalid_on_path(np.zeros((1, 7)), step) == (-1, -1)


def test_core_equals_reference_with_objects_modelled_by_their_points(planner, table_cloud, rng):
    """Neighbours as point columns (never cleared, every sphere): the C++ checker answers as the
    reference on random, near-boundary and hand states around them, with and without target
    contact; and a column stops a hand that its box would have stopped."""
    from types import SimpleNamespace
    from grasp_pipeline.motion.object_points import column_tops
    boxes = [OrientedBox(np.array([0.55, 0.0, 0.25]), np.eye(3), np.array([0.05, 0.06, 0.1])),
             OrientedBox(np.array([0.55, 0.09, 0.26]), np.eye(3), np.array([0.06, 0.06, 0.12]))]
    a, r = rng.uniform(0, 2 * np.pi, 3000), 0.03 * np.sqrt(rng.uniform(0, 1, 3000))
    bottle = np.c_[0.55 + r * np.cos(a), 0.09 + r * np.sin(a), np.full(3000, 0.32)]  # its cap seen from above
    tops = [None, column_tops(bottle, 0.005)]
    plane = SimpleNamespace(n=np.array([0.0, 0.0, 1.0]), c=-0.2)
    planner.set_scene(table_cloud(rng, n=40000), boxes, target_index=0, object_tops=tops, plane=plane)
    v = planner.validator
    assert v.boxes == [] and v.points is not None and len(v.points.points) > 10 * len(tops[1])
    T = planner.ik.fk_tcp(rm.READY_Q)
    T[:3, 3] = [0.55, 0.04, 0.30]
    q_t = planner.ik.solve_tcp(T, rm.READY_Q).q
    try:
        for allow in (False, True):
            v.allow_target_contact = allow
            Q = np.vstack([rng.uniform(v.q_min, v.q_max, size=(1500, 7)), _near_boundary(v, rng, 100),
                           q_t + rng.normal(0.0, 0.05, size=(1500, 7))])
            ok = _compare(v, Q)
            assert 0.05 * len(Q) < ok.sum() < 0.95 * len(Q)
    finally:
        v.allow_target_contact = False
    T[:3, 3] = [0.55, 0.09, 0.30]  # the hand inside the bottle
    q_in = planner.ik.solve_tcp(T, rm.READY_Q).q
    assert not v.is_valid(q_in) and "object's points" in v.explain(q_in)
