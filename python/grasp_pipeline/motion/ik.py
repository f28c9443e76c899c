"""Inverse kinematics of the Panda flange / TCP, verified on our MuJoCo model.

Choice (documented): candidates come from the analytic Panda IK of PyPI ``frankik``
(MIT; the field's closed-form solver, He & Liu style, parameterised by joint 7). Its
``ik``/``ik_full`` take the *flange* pose (its ``fk`` returns the Franka Hand TCP — the
two are not inverses of each other). For ``ik_q7_samples`` values of q7 across its range
plus the current q7, ``ik_full`` gives up to four solutions each. Every candidate is then

1. kept only if within our joint limits (``PANDA_Q_MIN/MAX``),
2. refined by Gauss-Newton on *our* model's forward kinematics (the robot-only MJCF's chain,
   exported once to the C++ core: ``_core.ArmIK``, equal to ``mj_kinematics`` to ~1e-15), so a
   difference between frankik's DH figures and our model cannot leak into the result,
3. verified on the same FK: accepted only if the flange reaches the target within
   ``ik_accept_position_m`` / ``ik_accept_orientation_rad``.

The solutions are de-duplicated and sorted by joint-space distance to the current joints;
the nearest is chosen. When frankik yields nothing usable, a damped-least-squares search on
our FK from the current joints (and the ready/neutral poses) is tried; if that also fails
the pose is unreachable and :class:`UnreachablePoseError` reports the closest reach
(position and orientation residual).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import mujoco
import numpy as np

from .. import _core
from ..robot import description as rm
from .config import MotionConfig
from .core_checker import chain_rows
from .exceptions import UnreachablePoseError
from .kinematics import ChainKinematics
from .poses import pose_error, pose_inverse, rotation_log, validate_joints, validate_pose

log = logging.getLogger(__name__)

#: Not tuning (the search's parameters are motion.yaml's ``ik_dls_*``):
#: a refined solution may exceed a joint limit by this rounding slack [rad] ...
_LIMIT_EPS_RAD = 1e-9
#: ... and up to this many states, MuJoCo's own Jacobians are faster than the vectorised chain.
_MJ_JACOBIAN_MAX_BATCH = 8


@dataclass(frozen=True)
class IKResult:
    """The chosen joints ``q`` (7,), every distinct solution found ``solutions`` (S, 7)
    sorted by distance to the current joints (``q`` first), and the chosen solution's
    residual measured with MuJoCo FK."""

    q: np.ndarray
    solutions: np.ndarray
    position_residual_m: float
    orientation_residual_rad: float


class PandaIK:
    """IK for the flange or the TCP of our Panda model (robot base = world origin)."""

    def __init__(self, config: MotionConfig, model: mujoco.MjModel | None = None) -> None:
        self.config = config
        self.model = model if model is not None else rm.load_robot_model()
        self.data = mujoco.MjData(self.model)
        self.arm_idx = rm.arm_qpos_indices(self.model)
        self.flange_id = self.model.body(rm.FLANGE_BODY).id
        self.q_min = np.asarray(rm.PANDA_Q_MIN, dtype=float)
        self.q_max = np.asarray(rm.PANDA_Q_MAX, dtype=float)
        self.arm_dof = rm.arm_dof_indices(self.model)
        self.kin = ChainKinematics(self.model, self.arm_idx)
        jid = [self.model.joint(n).id for n in rm.PANDA_JOINT_NAMES]
        self._arm_bodies = [int(self.model.jnt_bodyid[j]) for j in jid]
        self._arm_axes = [np.array(self.model.jnt_axis[j]) for j in jid]
        self._arm_anchor = [np.array(self.model.jnt_pos[j]) for j in jid]
        self.flange_T_tcp = rm.flange_T_tcp(self.model)
        self.tcp_T_flange = pose_inverse(self.flange_T_tcp)
        self.core = _core.ArmIK(chain_rows(self.kin, self.model.qpos0), self.flange_id, self.q_min, self.q_max,
                                config.ik_refine_iterations, config.ik_tolerance_m, config.ik_tolerance_rad,
                                config.ik_accept_position_m, config.ik_accept_orientation_rad, _LIMIT_EPS_RAD)

    # ------------------------------------------------------------------ forward kinematics
    def fk_flange(self, q: np.ndarray) -> np.ndarray:
        """Flange pose by ``mujoco.mj_kinematics`` on the robot model."""
        self.data.qpos[:] = self.model.qpos0
        self.data.qpos[self.arm_idx] = q
        mujoco.mj_kinematics(self.model, self.data)
        T = np.eye(4)
        T[:3, :3] = self.data.xmat[self.flange_id].reshape(3, 3)
        T[:3, 3] = self.data.xpos[self.flange_id]
        return T

    def fk_tcp(self, q: np.ndarray) -> np.ndarray:
        return self.fk_flange(q) @ self.flange_T_tcp

    # ------------------------------------------------------------------ IK
    def solve_tcp(self, T_world_tcp: np.ndarray, q_current: np.ndarray,
                  q7_samples: int | None = None) -> IKResult:
        """IK for a TCP pose (z = approach, y = closing); see :meth:`solve_flange`."""
        T = validate_pose(T_world_tcp, "TCP target pose")
        return self.solve_flange(T @ self.tcp_T_flange, q_current, q7_samples)

    def solve_flange(self, T_world_flange: np.ndarray, q_current: np.ndarray,
                     q7_samples: int | None = None) -> IKResult:
        """All solutions within the joint limits, the one nearest ``q_current`` chosen;
        ``q7_samples``: joint-7 samples of the analytic solver (default ``ik_q7_samples``; fewer
        find fewer of the solutions, faster — enough to tell whether a pose is reachable).

        Raises InvalidPoseError (NaN / malformed pose or joints) or UnreachablePoseError.
        """
        T = validate_pose(T_world_flange, "flange target pose")
        q_cur = validate_joints(q_current, "current joints")
        cands = self._analytic_candidates(T, q_cur, q7_samples)
        sols = self._refine_and_verify(T, cands) if len(cands) else np.zeros((0, 7))
        if len(sols) == 0:
            seeds = np.vstack([np.clip(q_cur, self.q_min, self.q_max), rm.READY_Q, rm.NEUTRAL_Q])
            best_q, pos_err, rot_err = self._dls_best(T, seeds)
            if pos_err <= self.config.ik_accept_position_m and rot_err <= self.config.ik_accept_orientation_rad:
                sols = best_q[None]
            else:
                raise UnreachablePoseError(
                    "pose unreachable: no IK solution within the joint limits "
                    f"(target flange position {np.round(T[:3, 3], 4).tolist()} m); "
                    f"closest reach is {pos_err * 1e3:.1f} mm / {np.degrees(rot_err):.2f} deg away "
                    f"(position / orientation residual); {len(cands)} analytic candidates were "
                    "within the joint limits",
                    position_residual_m=pos_err, orientation_residual_rad=rot_err)
        order = np.argsort(np.linalg.norm(sols - q_cur, axis=1), kind="stable")
        sols = sols[order]
        pos_err, rot_err = pose_error(T, self.fk_flange(sols[0]))
        return IKResult(q=sols[0].copy(), solutions=sols, position_residual_m=pos_err,
                        orientation_residual_rad=rot_err)

    # ------------------------------------------------------------------ internals
    def _analytic_candidates(self, T: np.ndarray, q_cur: np.ndarray, q7_samples: int | None = None) -> np.ndarray:
        import frankik

        n = self.config.ik_q7_samples if q7_samples is None else int(q7_samples)
        q7s = np.concatenate([[np.clip(q_cur[6], self.q_min[6], self.q_max[6])],
                              np.linspace(self.q_min[6], self.q_max[6], n)])
        out = []
        Tc = np.ascontiguousarray(T)
        for q7 in q7s:
            sols = np.asarray(frankik.ik_full(Tc, q_cur, float(q7), False))
            sols = sols[np.all(np.isfinite(sols), axis=1)]
            if len(sols):
                out.append(sols)
        if not out:
            return np.zeros((0, 7))
        c = np.vstack(out)
        inside = np.all((c >= self.q_min - 1e-6) & (c <= self.q_max + 1e-6), axis=1)
        return np.clip(c[inside], self.q_min, self.q_max)

    def _flange_and_jacobian(self, Q: np.ndarray):
        """Flange rotations (N, 3, 3), positions (N, 3) and 6x7 Jacobians (N, 6, 7) of our
        model: ``mj_kinematics`` + ``mj_comPos`` + ``mj_jacBody`` per state."""
        Q = np.atleast_2d(Q)
        n = len(Q)
        if n > _MJ_JACOBIAN_MAX_BATCH:
            return self._flange_and_jacobian_batch(Q)
        m, d = self.model, self.data
        Rf = np.empty((n, 3, 3))
        pf = np.empty((n, 3))
        J = np.empty((n, 6, 7))
        jacp = np.empty((3, m.nv))
        jacr = np.empty((3, m.nv))
        d.qpos[:] = m.qpos0
        for k in range(n):
            d.qpos[self.arm_idx] = Q[k]
            mujoco.mj_kinematics(m, d)
            mujoco.mj_comPos(m, d)
            mujoco.mj_jacBody(m, d, jacp, jacr, self.flange_id)
            Rf[k] = d.xmat[self.flange_id].reshape(3, 3)
            pf[k] = d.xpos[self.flange_id]
            J[k, :3] = jacp[:, self.arm_dof]
            J[k, 3:] = jacr[:, self.arm_dof]
        return Rf, pf, J

    def _flange_and_jacobian_batch(self, Q: np.ndarray):
        """Same as :meth:`_flange_and_jacobian`, vectorised with :class:`ChainKinematics`
        (faster for many candidates; identical to MuJoCo's FK to ~1e-15)."""
        R, p = self.kin.body_poses(Q, bodies_needed=self.flange_id + 1)
        Rf, pf = R[:, self.flange_id], p[:, self.flange_id]
        J = np.empty((len(Q), 6, 7))
        for j, (b, ax, an) in enumerate(zip(self._arm_bodies, self._arm_axes, self._arm_anchor)):
            z = R[:, b] @ ax
            a = p[:, b] + R[:, b] @ an
            J[:, :3, j] = np.cross(z, pf - a)
            J[:, 3:, j] = z
        return Rf, pf, J

    def _errors(self, T: np.ndarray, Rf: np.ndarray, pf: np.ndarray) -> np.ndarray:
        from scipy.spatial.transform import Rotation

        e = np.empty((len(pf), 6))
        e[:, :3] = T[:3, 3] - pf
        e[:, 3:] = Rotation.from_matrix(T[:3, :3][None] @ np.transpose(Rf, (0, 2, 1))).as_rotvec()
        return e

    def _refine_and_verify(self, T: np.ndarray, Q: np.ndarray) -> np.ndarray:
        """Gauss-Newton refinement of every seed row of Q (C++ ``ArmIK.refine_batch``: up to
        ``ik_refine_iterations`` steps, kept when inside the limits and verified), then the
        kept solutions without duplicates (max joint difference ≤ ``ik_duplicate_tol_rad``)."""
        Qr, ok = self.core.refine_batch(T, np.asarray(Q, dtype=float))
        keep = Qr[ok]
        if not len(keep):
            return np.zeros((0, 7))
        uniq = [keep[0]]
        for q in keep[1:]:
            if np.min(np.max(np.abs(np.asarray(uniq) - q), axis=1)) > self.config.ik_duplicate_tol_rad:
                uniq.append(q)
        return np.asarray(uniq)

    def refine_line(self, Ts: np.ndarray, q_start: np.ndarray) -> np.ndarray:
        """Refine the flange poses Ts (n, 4, 4) in order, each seeded by the previous solution:
        the solved prefix (k, 7); k < n when pose k needs another method (see :meth:`solve_flange`)."""
        return self.core.refine_line(Ts, q_start)

    def _dls_best(self, T: np.ndarray, seeds: np.ndarray) -> tuple[np.ndarray, float, float]:
        """Damped least squares with joint-limit clamping from each seed; the best reach.

        Orientation rows are weighted by ``ik_dls_orientation_weight_m_per_rad`` so an
        unreachable target still yields a meaningful closest *position*; the other ``ik_dls_*``
        parameters of ``config/motion.yaml`` set the iterations, damping and step clamps.
        """
        cfg = self.config
        w_rot = cfg.ik_dls_orientation_weight_m_per_rad
        Q = seeds.astype(float).copy()
        W = np.diag([1.0, 1.0, 1.0] + [w_rot] * 3)[None]
        half = cfg.ik_dls_iterations // 2
        for it in range(cfg.ik_dls_iterations):
            lam2 = (cfg.ik_dls_damping_late if it > half else cfg.ik_dls_damping_early) ** 2
            Rf, pf, J = self._flange_and_jacobian(Q)
            e6 = self._errors(T, Rf, pf)
            # clamp the task-space error: small steps keep DLS stable far from the target
            pn = np.linalg.norm(e6[:, :3], axis=1, keepdims=True)
            rn = np.linalg.norm(e6[:, 3:], axis=1, keepdims=True)
            e6[:, :3] *= np.minimum(1.0, cfg.ik_dls_max_step_m / np.maximum(pn, 1e-12))
            e6[:, 3:] *= np.minimum(1.0, cfg.ik_dls_max_step_rad / np.maximum(rn, 1e-12))
            e = W @ e6[:, :, None]
            Jw = W @ J
            JT = np.transpose(Jw, (0, 2, 1))
            step = JT @ np.linalg.solve(Jw @ JT + lam2 * np.eye(6)[None], e)
            Q = np.clip(Q + step[:, :, 0], self.q_min, self.q_max)
        best = None
        for q in Q:
            pe, re = pose_error(T, self.fk_flange(q))
            score = pe + w_rot * re
            if best is None or score < best[0]:
                best = (score, q, pe, re)
        return best[1], best[2], best[3]

def rotvec_error(T_target: np.ndarray, T: np.ndarray) -> np.ndarray:
    """6-vector (position error, rotation-vector error) in world coordinates."""
    return np.concatenate([T_target[:3, 3] - T[:3, 3], rotation_log(T_target[:3, :3] @ T[:3, :3].T)])
