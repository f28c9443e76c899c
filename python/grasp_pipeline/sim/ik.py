"""A small damped-least-squares IK on the MuJoCo robot model — for tests, tools and the
simulator benchmark (the pipeline's motion layer has its own IK and planner).

``solve_ik(T_target, q_seed)`` moves a frame fixed to the flange (default: the flange itself,
or pass ``flange_T_frame``, e.g. :func:`~.robot_model.flange_T_tcp`) onto ``T_target``.
Joint limits are respected by clipping every iteration.
"""

from __future__ import annotations

import mujoco
import numpy as np

from ..robot.description import (
    FLANGE_BODY,
    PANDA_Q_MAX,
    PANDA_Q_MIN,
    arm_dof_indices,
    arm_qpos_indices,
    load_robot_model,
)

IK_MAX_ITERS = 300
IK_DAMPING = 1e-3
IK_POS_TOL_M = 1e-6
IK_ROT_TOL_RAD = 1e-6
#: Largest joint change per iteration [rad] (keeps the iteration on one IK branch).
IK_MAX_STEP_RAD = 0.2


def _rot_error(R_cur: np.ndarray, R_goal: np.ndarray) -> np.ndarray:
    """Rotation vector (world frame) taking R_cur to R_goal."""
    q = np.empty(4)
    mujoco.mju_mat2Quat(q, (R_goal @ R_cur.T).reshape(-1))
    v = np.empty(3)
    mujoco.mju_quat2Vel(v, q, 1.0)
    return v


def solve_ik(T_target: np.ndarray, q_seed: np.ndarray, flange_T_frame: np.ndarray | None = None,
             model: mujoco.MjModel | None = None) -> tuple[np.ndarray, bool]:
    """Joints placing ``flange_T_frame`` (default identity) at ``T_target`` (4x4, world).

    Returns ``(q, converged)``; ``q`` is the best found even when not converged.
    """
    m = model if model is not None else load_robot_model()
    d = mujoco.MjData(m)
    qi, di = arm_qpos_indices(m), arm_dof_indices(m)
    bid = m.body(FLANGE_BODY).id
    F = np.eye(4) if flange_T_frame is None else np.asarray(flange_T_frame, dtype=float)
    q = np.clip(np.asarray(q_seed, dtype=float).copy(), PANDA_Q_MIN, PANDA_Q_MAX)
    jacp = np.zeros((3, m.nv))
    jacr = np.zeros((3, m.nv))
    ok = False
    for _ in range(IK_MAX_ITERS):
        d.qpos[qi] = q
        mujoco.mj_kinematics(m, d)
        mujoco.mj_comPos(m, d)
        Rf = d.xmat[bid].reshape(3, 3)
        p = d.xpos[bid] + Rf @ F[:3, 3]
        R = Rf @ F[:3, :3]
        e = np.concatenate([T_target[:3, 3] - p, _rot_error(R, T_target[:3, :3])])
        if np.linalg.norm(e[:3]) < IK_POS_TOL_M and np.linalg.norm(e[3:]) < IK_ROT_TOL_RAD:
            ok = True
            break
        mujoco.mj_jac(m, d, jacp, jacr, p, bid)
        J = np.vstack([jacp[:, di], jacr[:, di]])
        dq = J.T @ np.linalg.solve(J @ J.T + IK_DAMPING * np.eye(6), e)
        scale = max(1.0, np.abs(dq).max() / IK_MAX_STEP_RAD)
        q = np.clip(q + dq / scale, PANDA_Q_MIN, PANDA_Q_MAX)
    return q, ok
