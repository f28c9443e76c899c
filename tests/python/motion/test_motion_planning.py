"""Joint planning around a perceived obstacle, refusals, Cartesian lines, TOPP-RA timing."""

import numpy as np
import pytest

from grasp_pipeline.motion.exceptions import (CartesianPathError, GoalInCollisionError,
                                              StartInCollisionError, TimeParameterizationError)
from grasp_pipeline.motion.timing import TrajectoryTimer
from grasp_pipeline.robot import description as rm

LIMIT_TOL = 0.01  # ≤ 1 % over the scaled limits at any sample


def _tcp_down(x, y, z):
    """TCP pose looking straight down (z = -world z) at (x, y, z)."""
    T = np.eye(4)
    T[:3, :3] = np.array([[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]])
    T[:3, 3] = (x, y, z)
    return T


@pytest.fixture()
def wall_scene(planner, rng, table_cloud, box_cloud):
    """Table + a perceived box-shaped obstacle between two down-looking poses."""
    pts = np.vstack([table_cloud(rng), box_cloud((0.40, -0.05, 0.2), (0.50, 0.05, 0.45))])
    planner.set_scene(pts)
    qa = planner.solve_ik(_tcp_down(0.45, -0.25, 0.35), rm.READY_Q).q
    qb = planner.solve_ik(_tcp_down(0.45, 0.25, 0.35), rm.READY_Q).q
    yield qa, qb
    planner.set_scene(np.zeros((0, 3)))


def _dense_states(wp, step):
    out = [wp[:1]]
    for a, b in zip(wp[:-1], wp[1:]):
        n = max(1, int(np.ceil(np.max(np.abs(b - a)) / step)))
        out.append(a + (b - a) * (np.arange(1, n + 1)[:, None] / n))
    return np.vstack(out)


def test_plan_around_perceived_obstacle(planner, wall_scene):
    qa, qb = wall_scene
    v = planner.validator
    step = np.radians(0.5)
    straight = _dense_states(np.vstack([qa, qb]), step)
    assert v.is_valid(qa) and v.is_valid(qb)
    assert not np.all(v.check_batch(straight)), "the straight joint line must hit the obstacle"
    path = planner.plan_path_to_joints(qa, qb)
    assert path.method == planner.config.planner and path.attempts >= 1
    assert np.allclose(path.waypoints[0], qa) and np.allclose(path.waypoints[-1], qb)
    dense = _dense_states(path.waypoints, step)
    assert np.all(v.check_batch(dense))
    traj = planner.time_path(path)
    assert np.all(v.check_batch(traj.q[::5]))  # timed samples too (the spline stays clear)
    assert np.allclose(traj.q[0], qa) and np.allclose(traj.q[-1], qb)


def test_start_and_goal_in_collision_refused(planner, wall_scene):
    qa, _ = wall_scene
    q_hit = planner.solve_ik(_tcp_down(0.45, 0.0, 0.35), rm.READY_Q).q
    with pytest.raises(StartInCollisionError, match="perceived environment"):
        planner.plan_path_to_joints(q_hit, qa)
    with pytest.raises(GoalInCollisionError, match="perceived environment"):
        planner.plan_path_to_joints(qa, q_hit)
    with pytest.raises(GoalInCollisionError):
        planner.plan_path_to_pose(qa, _tcp_down(0.45, 0.0, 0.35))


def test_direct_line_when_free(planner):
    planner.set_scene(np.zeros((0, 3)))
    p = planner.plan_path_to_joints(rm.READY_Q, rm.NEUTRAL_Q)
    assert p.method == "direct" and p.attempts == 0 and len(p.waypoints) == 2


def test_cartesian_line_and_target_region(planner, rng, table_cloud, box_cloud):
    from grasp_pipeline.motion.occupancy import OrientedBox

    cube = box_cloud((0.475, -0.025, 0.2), (0.525, 0.025, 0.25))
    planner.set_scene(table_cloud(rng), [OrientedBox(np.array([0.5, 0.0, 0.225]), np.eye(3),
                                                     np.full(3, 0.05))])
    T_grasp = _tcp_down(0.5, 0.0, 0.225)
    T_pre = _tcp_down(0.5, 0.0, 0.325)
    planner.set_target(0)
    q_pre = planner.solve_ik(T_pre, rm.READY_Q).q
    path = planner.plan_path_cartesian(q_pre, T_grasp, "tcp", allow_target_contact=True)
    assert path.method == "cartesian"
    tcp = np.array([planner.ik.fk_tcp(q)[:3, 3] for q in path.waypoints])
    assert np.max(np.abs(tcp[:, :2] - [0.5, 0.0])) < 1e-5            # a straight vertical line
    assert np.max(np.abs(np.diff(path.waypoints, axis=0))) <= planner.config.cartesian_max_joint_step_rad
    # without the target exception the fingers may not go down next to the cube into the table
    planner.set_scene(np.vstack([table_cloud(rng), cube]))
    with pytest.raises(CartesianPathError, match="blocked"):
        planner.plan_path_cartesian(q_pre, T_grasp, "tcp", allow_target_contact=False)
    # an unreachable line says so
    with pytest.raises(CartesianPathError):
        planner.plan_path_cartesian(q_pre, _tcp_down(1.6, 0.0, 0.3), "tcp")
    planner.set_scene(np.zeros((0, 3)))


def test_toppra_limits_respected(planner, rng):
    timer = planner.timer
    cfg = planner.config
    vlim = rm.PANDA_QD_MAX * cfg.velocity_scale
    alim = rm.PANDA_QDD_MAX * cfg.acceleration_scale
    for m in (2, 3, 6):
        wp = rng.uniform(rm.PANDA_Q_MIN + 0.3, rm.PANDA_Q_MAX - 0.3, size=(m, 7))
        tr = timer.time_path(wp)
        assert np.all(np.abs(tr.qd) <= vlim * (1 + LIMIT_TOL))
        assert np.all(np.abs(tr.qdd) <= alim * (1 + LIMIT_TOL))
        assert np.allclose(tr.q[0], wp[0]) and np.allclose(tr.q[-1], wp[-1])
        assert np.allclose(tr.qd[0], 0) and np.allclose(tr.qd[-1], 0)
        dt = np.diff(tr.t_s)
        assert np.all(dt > 0) and np.all(dt <= 1.0 / cfg.control_rate_hz + 1e-9)
        # the velocity limit is actually reached on a long move (time-optimal, not over-slow)
        if m == 2:
            assert np.max(np.abs(tr.qd) / vlim) > 0.9
        # samples are consistent: integrating qd gives q
        q_int = tr.q[0] + np.cumsum(0.5 * (tr.qd[1:] + tr.qd[:-1]) * dt[:, None], axis=0)
        assert np.max(np.abs(q_int[-1] - tr.q[-1])) < 5e-3


def test_toppra_bad_input(planner):
    with pytest.raises(TimeParameterizationError):
        planner.timer.time_path(np.full((3, 7), np.nan))
    hold = planner.timer.time_path(np.vstack([rm.READY_Q, rm.READY_Q]))
    assert hold.num_samples == 1 and hold.duration_s == 0.0


def test_timer_uses_scaled_limits(motion_config):
    t = TrajectoryTimer(rm.PANDA_QD_MAX, rm.PANDA_QDD_MAX, motion_config)
    assert np.allclose(t.qd_limit, rm.PANDA_QD_MAX * 0.3)
    assert np.allclose(t.qdd_limit, rm.PANDA_QDD_MAX * 0.3)


def test_stop_at_waypoints_timing_follows_polyline(planner, rng):
    cfg = planner.config
    wp = rng.uniform(rm.PANDA_Q_MIN + 0.3, rm.PANDA_Q_MAX - 0.3, size=(3, 7))
    tr = planner.timer.time_path_stop_at_waypoints(wp)
    assert np.all(np.abs(tr.qd) <= rm.PANDA_QD_MAX * cfg.velocity_scale * (1 + LIMIT_TOL))
    assert np.all(np.abs(tr.qdd) <= rm.PANDA_QDD_MAX * cfg.acceleration_scale * (1 + LIMIT_TOL))
    # the middle waypoint is passed exactly, at rest
    k = int(np.argmin(np.linalg.norm(tr.q - wp[1], axis=1)))
    assert np.linalg.norm(tr.q[k] - wp[1]) < 1e-9 and np.max(np.abs(tr.qd[k])) < 1e-6
    # every sample lies on one of the two segments
    for q in tr.q[::50]:
        d = min(np.linalg.norm((q - a) - np.clip(np.dot(q - a, b - a) / np.dot(b - a, b - a), 0, 1) * (b - a))
                for a, b in ((wp[0], wp[1]), (wp[1], wp[2])))
        assert d < 1e-6


def test_timing_samples_equal_the_trajectory_calls(motion_config):
    """The one-pass sampling gives the very values of ``traj(t)``, ``traj(t, 1)``, ``traj(t, 2)``."""
    import toppra
    import toppra.algorithm as algo
    import toppra.constraint as constraint

    from grasp_pipeline.motion.timing import _evaluate

    t = TrajectoryTimer(rm.PANDA_QD_MAX, rm.PANDA_QDD_MAX, motion_config)
    wp = np.array([rm.READY_Q, rm.READY_Q + 0.3, rm.READY_Q - 0.2])
    ss = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(wp, axis=0), axis=1))]
    cons = [constraint.JointVelocityConstraint(np.stack([-t.qd_limit, t.qd_limit], axis=1)),
            constraint.JointAccelerationConstraint(np.stack([-t.qdd_limit, t.qdd_limit], axis=1))]
    traj = algo.TOPPRA(cons, toppra.SplineInterpolator(ss, wp), gridpoints=np.linspace(0, ss[-1], 50),
                       parametrizer="ParametrizeConstAccel").compute_trajectory(0.0, 0.0)
    tau = np.linspace(0.0, float(traj.duration), 301)
    for got, want in zip(_evaluate(traj, tau), (traj(tau), traj(tau, 1), traj(tau, 2))):
        assert np.array_equal(got, want)


def test_self_filter_drops_exactly_the_points_in_the_spheres(planner, rng):
    """The robot's self-filter (its quick no-point-near test included) drops the points within
    the padded spheres and keeps every other, near or far."""
    from grasp_pipeline.motion.motion_planner import may_touch_spheres

    q = rm.READY_Q
    C = planner.robot.centres(q[None])[0]
    r = planner.robot.spheres.radius + planner.config.self_filter_padding_m
    far = np.column_stack([rng.uniform(0.3, 0.8, 4000), rng.uniform(-0.4, 0.4, 4000), np.zeros(4000)])
    assert not may_touch_spheres(far, C, r)
    near = C[rng.integers(0, len(C), 3000)] + rng.normal(scale=0.03, size=(3000, 3))
    pts = np.vstack([far, near])
    d = np.min(np.linalg.norm(pts[:, None] - C[None], axis=2) - r[None], axis=1)
    assert np.min(np.abs(d)) > 1e-9  # no point on a sphere's surface: the brute force decides
    kept = planner._self_filter(pts, q)
    assert np.array_equal(kept, pts[d > 0]) and len(kept) < len(pts)
    assert np.array_equal(planner._self_filter(far, q), far)
