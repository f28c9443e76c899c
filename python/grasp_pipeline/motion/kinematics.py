"""Vectorised forward kinematics of the robot model (our MJCF), for many states at once.

The IK refines up to a few hundred analytic candidates at once; a Python loop of
``mujoco.mj_kinematics`` + ``mj_jacBody`` per candidate is slower than one vectorised pass.
This class reads the kinematic tree from the ``MjModel`` (body offsets, joint axes,
anchors, ``qpos0``) and replays MuJoCo's own recursion with numpy over a batch of states.
It is checked against ``mj_kinematics`` to ~1e-12 in the tests, and every IK solution is
finally verified with ``mj_kinematics`` itself. (The collision spheres are posed with
``mj_kinematics`` directly: for one state at a time that is faster.)

Only hinge and slide joints are supported (the Panda has nothing else). Joints that are
not arm joints (the fingers) take fixed values given at call time.
"""

from __future__ import annotations

import mujoco
import numpy as np


def _quat_to_mat(q: np.ndarray) -> np.ndarray:
    m = np.empty(9)
    mujoco.mju_quat2Mat(m, np.asarray(q, dtype=float))
    return m.reshape(3, 3)


def _axis_angle_batch(axis: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """(N, 3, 3) rotations about one unit ``axis`` by ``angle`` (N,) (Rodrigues)."""
    x, y, z = axis
    K = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    K2 = K @ K
    s = np.sin(angle)[:, None, None]
    c = (1.0 - np.cos(angle))[:, None, None]
    return np.eye(3)[None] + s * K[None] + c * K2[None]


class ChainKinematics:
    """Batch FK over the model's bodies.

    ``arm_qpos_idx``: the qpos addresses driven by the batch (the 7 arm joints, in order).
    Every other joint is set from ``fixed_qpos`` (a full ``qpos`` vector) at call time.
    """

    def __init__(self, model: mujoco.MjModel, arm_qpos_idx: np.ndarray) -> None:
        self.model = model
        self.nbody = int(model.nbody)
        self.arm_qpos_idx = np.asarray(arm_qpos_idx, dtype=int)
        self._col_of_qpos = {int(a): i for i, a in enumerate(self.arm_qpos_idx)}
        self.parent = np.array(model.body_parentid, dtype=int)
        self.body_pos = np.array(model.body_pos, dtype=float)
        self.body_R = np.stack([_quat_to_mat(model.body_quat[b]) for b in range(self.nbody)])
        self.joints: list[list[tuple[int, int, np.ndarray, np.ndarray, float]]] = []
        for b in range(self.nbody):
            js = []
            for j in range(model.body_jntadr[b], model.body_jntadr[b] + model.body_jntnum[b]):
                jt = int(model.jnt_type[j])
                if jt not in (mujoco.mjtJoint.mjJNT_HINGE, mujoco.mjtJoint.mjJNT_SLIDE):
                    raise ValueError(f"joint {model.joint(j).name!r}: only hinge/slide joints supported")
                adr = int(model.jnt_qposadr[j])
                js.append((jt, adr, np.array(model.jnt_axis[j], dtype=float),
                           np.array(model.jnt_pos[j], dtype=float), float(model.qpos0[adr])))
            self.joints.append(js)
        self.default_qpos = np.array(model.qpos0, dtype=float)
        # bodies whose pose depends on an arm joint (the rest never moves)
        moving = np.zeros(self.nbody, dtype=bool)
        for b in range(1, self.nbody):
            own = any(adr in self._col_of_qpos for _, adr, _, _, _ in self.joints[b])
            moving[b] = own or moving[self.parent[b]]
        self.moving = moving

    def body_poses(self, Q: np.ndarray, fixed_qpos: np.ndarray | None = None,
                   bodies_needed: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """World rotations (N, nbody, 3, 3) and positions (N, nbody, 3) for arm states Q (N, 7).

        ``bodies_needed``: compute bodies ``0 .. bodies_needed-1`` only (tree order).
        """
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        n = len(Q)
        qfix = self.default_qpos if fixed_qpos is None else np.asarray(fixed_qpos, dtype=float)
        nb = self.nbody if bodies_needed is None else bodies_needed
        R = np.empty((n, nb, 3, 3))
        p = np.empty((n, nb, 3))
        R[:, 0] = np.eye(3)
        p[:, 0] = 0.0
        for b in range(1, nb):
            par = self.parent[b]
            Rb = R[:, par] @ self.body_R[b]
            pb = p[:, par] + R[:, par] @ self.body_pos[b]
            for jt, adr, axis, anchor, q0 in self.joints[b]:
                col = self._col_of_qpos.get(adr)
                val = (Q[:, col] if col is not None else np.full(n, qfix[adr])) - q0
                if jt == mujoco.mjtJoint.mjJNT_HINGE:
                    anchor_w = pb + Rb @ anchor
                    Rb = Rb @ _axis_angle_batch(axis, val)
                    pb = anchor_w - Rb @ anchor
                else:
                    pb = pb + (Rb @ axis) * val[:, None]
            R[:, b] = Rb
            p[:, b] = pb
        return R, p

    def body_pose(self, q: np.ndarray, body_id: int, fixed_qpos: np.ndarray | None = None) -> np.ndarray:
        """4x4 world pose of one body for one arm state."""
        R, p = self.body_poses(np.asarray(q, dtype=float)[None], fixed_qpos, bodies_needed=body_id + 1)
        T = np.eye(4)
        T[:3, :3] = R[0, body_id]
        T[:3, 3] = p[0, body_id]
        return T
