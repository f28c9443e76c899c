"""IK: round trips on our model's FK, nearest-solution choice, clear refusals."""

import numpy as np
import pytest

from grasp_pipeline.motion.exceptions import InvalidPoseError, UnreachablePoseError
from grasp_pipeline.motion.poses import pose_error
from grasp_pipeline.robot import description as rm

MARGIN_RAD = 0.05


def _random_q(rng, n):
    return rng.uniform(rm.PANDA_Q_MIN + MARGIN_RAD, rm.PANDA_Q_MAX - MARGIN_RAD, size=(n, 7))


def test_fk_matches_mujoco_model(planner, rng):
    """Our FK (used by the IK) is MuJoCo's FK of the robot model."""
    for q in _random_q(rng, 5):
        assert np.allclose(planner.ik.fk_flange(q), rm.forward_kinematics(q, planner.model), atol=1e-12)


def test_ik_round_trip_tcp_and_flange(planner, rng):
    worst = [0.0, 0.0]
    for q in _random_q(rng, 20):
        q_cur = np.clip(q + rng.normal(0.0, 0.3, 7), rm.PANDA_Q_MIN, rm.PANDA_Q_MAX)
        for frame in ("tcp", "flange"):
            T = planner.ik.fk_tcp(q) if frame == "tcp" else planner.ik.fk_flange(q)
            res = planner.solve_ik(T, q_cur, frame)
            T_back = planner.ik.fk_tcp(res.q) if frame == "tcp" else planner.ik.fk_flange(res.q)
            pe, re = pose_error(T, T_back)
            worst = [max(worst[0], pe), max(worst[1], re)]
            assert np.all(res.q >= rm.PANDA_Q_MIN) and np.all(res.q <= rm.PANDA_Q_MAX)
            assert res.position_residual_m <= 1e-6 and res.orientation_residual_rad <= 1e-6
    assert worst[0] <= 1e-6 and worst[1] <= 1e-6, worst


def test_ik_chooses_nearest_solution(planner, rng):
    for q in _random_q(rng, 8):
        res = planner.solve_ik(planner.ik.fk_tcp(q), q, "tcp")
        d = np.linalg.norm(res.solutions - q, axis=1)
        assert np.isclose(np.linalg.norm(res.q - q), d.min())
        assert np.all(np.diff(d) >= -1e-12)            # sorted by distance
        assert np.linalg.norm(res.q - q) < 1e-3         # the current joints solve it: chosen
    # every solution reaches the pose
    for s in res.solutions:
        pe, re = pose_error(planner.ik.fk_tcp(q), planner.ik.fk_tcp(s))
        assert pe <= 1e-6 and re <= 1e-6


def test_unreachable_pose_reports_residual(planner):
    T = planner.ik.fk_tcp(rm.READY_Q)
    T[0, 3] += 1.0
    with pytest.raises(UnreachablePoseError) as ei:
        planner.solve_ik(T, rm.READY_Q, "tcp")
    msg = str(ei.value)
    assert "unreachable" in msg and "mm" in msg and "deg" in msg
    assert 0.2 < ei.value.position_residual_m < 1.2


@pytest.mark.parametrize("bad", ["nan", "shape", "not_rotation"])
def test_malformed_pose_refused(planner, bad):
    T = planner.ik.fk_tcp(rm.READY_Q)
    if bad == "nan":
        T[1, 3] = np.nan
    elif bad == "shape":
        T = T[:3]
    else:
        T[:3, :3] *= 2.0
    with pytest.raises(InvalidPoseError):
        planner.solve_ik(T, rm.READY_Q, "tcp")
    with pytest.raises(InvalidPoseError):
        planner.plan_path_to_pose(rm.READY_Q, T)


def test_nan_current_joints_refused(planner):
    q = np.array(rm.READY_Q, dtype=float)
    q[3] = np.nan
    with pytest.raises(InvalidPoseError, match="NaN"):
        planner.solve_ik(planner.ik.fk_tcp(rm.READY_Q), q)
