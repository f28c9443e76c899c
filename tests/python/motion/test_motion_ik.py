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


def _numpy_refine_reference(ik, T, Q):
    """The numpy refinement the C++ ``ArmIK.refine_batch`` replaced (kept here as the
    reference): Gauss-Newton on MuJoCo's FK + Jacobian, limits, verification by MuJoCo FK."""
    cfg = ik.config
    Q = Q.copy()
    for _ in range(cfg.ik_refine_iterations):
        Rf, pf, J = ik._flange_and_jacobian(Q)
        e = ik._errors(T, Rf, pf)
        done = (np.linalg.norm(e[:, :3], axis=1) <= cfg.ik_tolerance_m) & \
               (np.linalg.norm(e[:, 3:], axis=1) <= cfg.ik_tolerance_rad)
        if np.all(done):
            break
        JT = np.transpose(J, (0, 2, 1))
        step = JT @ np.linalg.solve(J @ JT + 1e-12 * np.eye(6)[None], e[:, :, None])
        Q[~done] += step[~done, :, 0]
    inside = np.all((Q >= ik.q_min - 1e-9) & (Q <= ik.q_max + 1e-9), axis=1)
    Qc = np.clip(Q, ik.q_min, ik.q_max)
    ok = inside & np.array([all(e <= a for e, a in zip(pose_error(T, ik.fk_flange(q)),
                                                          (cfg.ik_accept_position_m, cfg.ik_accept_orientation_rad)))
                            for q in Qc])
    return Qc, ok


def test_core_refinement_equals_numpy_reference(planner, rng):
    """C++ refinement vs the numpy reference: the same seeds kept, the same joints (1e-9 rad),
    on the analytic candidates of random targets and on perturbed / far seeds."""
    ik = planner.ik
    compared, kept = 0, 0
    for q in _random_q(rng, 30):
        T = ik.fk_flange(q)
        seeds = np.vstack([ik._analytic_candidates(T, q)[:40], q + rng.normal(0.0, 0.05, (10, 7)),
                           _random_q(rng, 5)])
        Qr, ok = ik.core.refine_batch(T, seeds)
        Qn, ok_n = _numpy_refine_reference(ik, T, seeds)
        assert np.array_equal(ok, ok_n)
        assert np.abs(Qr[ok] - Qn[ok]).max(initial=0.0) <= 1e-9
        compared += len(seeds)
        kept += int(ok.sum())
    assert compared >= 1000 and 0.3 * compared < kept < compared


def test_core_ik_flange_pose_and_bad_input(planner, rng):
    ik = planner.ik
    for q in _random_q(rng, 5):
        assert np.abs(ik.core.flange_pose(q) - ik.fk_flange(q)).max() <= 1e-12
    with pytest.raises(ValueError, match=r"T: expected shape \(4, 4\)"):
        ik.core.refine_batch(np.eye(3), np.zeros((1, 7)))
    with pytest.raises(ValueError, match="finite"):
        ik.core.refine_line(np.full((2, 4, 4), np.nan), np.zeros(7))
    with pytest.raises(ValueError, match=r"q0: expected shape \(7,\)"):
        ik.core.refine_line(np.tile(np.eye(4), (2, 1, 1)), np.zeros(6))
    assert ik.core.refine_line(np.zeros((0, 4, 4)), rm.READY_Q).shape == (0, 7)


def test_refine_line_follows_a_straight_line(planner):
    """Each pose seeded by the previous solution: small joint steps, every pose reached."""
    ik = planner.ik
    T0 = ik.fk_flange(np.asarray(rm.READY_Q))
    Ts = np.tile(T0, (20, 1, 1))
    Ts[:, 2, 3] -= np.linspace(0.005, 0.1, 20)
    Q = ik.refine_line(Ts, np.asarray(rm.READY_Q))
    assert Q.shape == (20, 7)
    assert np.abs(np.diff(np.vstack([rm.READY_Q, Q]), axis=0)).max() < 0.05
    for T, q in zip(Ts, Q):
        pe, re = pose_error(T, ik.fk_flange(q))
        assert pe <= 1e-6 and re <= 1e-6
    far = Ts.copy()
    far[10:, 0, 3] += 3.0  # unreachable from pose 10 on: the solved prefix stops there
    assert ik.refine_line(far, np.asarray(rm.READY_Q)).shape == (10, 7)
