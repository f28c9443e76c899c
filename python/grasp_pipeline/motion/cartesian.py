"""Straight-line Cartesian segments (approach, lift) for the TCP or the flange.

The line from the current pose to the target is cut into poses every
``cartesian_step_m`` of translation and ``cartesian_step_rad`` of rotation (positions
linear, orientations by slerp). Each pose is solved by Gauss-Newton on our model's FK,
seeded with the previous solution (so the joints move continuously), then verified on the
same FK (residual ≤ ``ik_accept_position_m`` / ``ik_accept_orientation_rad``): one C++ call
(``PandaIK.refine_line``) for the whole line, the full IK only for a pose it cannot solve. A step
whose joints change by more than ``cartesian_max_joint_step_rad`` on any joint is a jump
(e.g. a wrist flip near a singularity) and is refused, as is leaving the joint limits.
Consecutive solutions are collision-checked densely (≤ ``final_check_step_rad``) with
the scene's validator, in path order in one C++ call; ``allow_target_contact`` lets the hand enter the target region.
"""

from __future__ import annotations

import time

import numpy as np
from scipy.spatial.transform import Rotation, Slerp

from .config import MotionConfig
from .exceptions import CartesianPathError, StartStateInvalidError, UnreachablePoseError
from .ik import PandaIK
from .poses import pose_error, validate_joints, validate_pose
from .trajectory import JointPath
from .validity import StateValidator


class CartesianPlanner:
    """Follows straight TCP/flange lines with continuity and collision checks."""

    def __init__(self, ik: PandaIK, validator: StateValidator, config: MotionConfig) -> None:
        self.ik = ik
        self.validator = validator
        self.config = config

    def plan(self, q_start: np.ndarray, T_goal: np.ndarray, frame: str = "tcp",
             allow_target_contact: bool = False) -> JointPath:
        """Joint path following the straight line to ``T_goal`` (``frame`` = "tcp" | "flange")."""
        t0, c0 = time.perf_counter(), time.thread_time()
        cfg = self.config
        q = validate_joints(q_start, "start joints")
        T_goal = validate_pose(T_goal, f"{frame} goal pose")
        if frame not in ("tcp", "flange"):
            raise ValueError(f"frame must be 'tcp' or 'flange', got {frame!r}")
        to_flange = self.ik.tcp_T_flange if frame == "tcp" else np.eye(4)
        T_goal_f = T_goal @ to_flange
        T_start_f = self.ik.fk_flange(q)
        dist = float(np.linalg.norm(T_goal_f[:3, 3] - T_start_f[:3, 3]))
        _, ang = pose_error(T_goal_f, T_start_f)
        n = max(1, int(np.ceil(dist / cfg.cartesian_step_m)), int(np.ceil(ang / cfg.cartesian_step_rad)))
        slerp = Slerp([0.0, 1.0], Rotation.from_matrix(np.stack([T_start_f[:3, :3], T_goal_f[:3, :3]])))
        s = np.arange(1, n + 1) / n
        Rs = slerp(s).as_matrix()
        Ps = T_start_f[:3, 3] + np.outer(s, T_goal_f[:3, 3] - T_start_f[:3, 3])
        v = self.validator
        prev_flag = v.allow_target_contact
        v.allow_target_contact = allow_target_contact
        n0 = v.checked_states
        try:
            if not v.is_valid(q):
                raise StartStateInvalidError(f"Cartesian segment start state is invalid: {v.explain(q)}")
            path = self._solve_line(Rs, Ps, q, dist)
            bad = v.first_invalid_state(path, cfg.final_check_step_rad)
            if bad is not None:
                k, q_bad = bad
                raise CartesianPathError(
                    f"Cartesian line blocked at {100.0 * s[k]:.0f} % of {dist * 1e3:.0f} mm: "
                    f"{v.explain(q_bad)}")
        finally:
            v.allow_target_contact = prev_flag
        return JointPath(path, (time.perf_counter() - t0) * 1e3, "cartesian", 0,
                         v.checked_states - n0, (time.thread_time() - c0) * 1e3)

    def _solve_line(self, Rs: np.ndarray, Ps: np.ndarray, q: np.ndarray, dist: float) -> np.ndarray:
        """Joints of every pose of the line (start q first): the C++ refinement seeded by the
        previous pose's joints; a pose it cannot solve goes through the full IK."""
        n = len(Ps)
        Ts = np.zeros((n, 4, 4))
        Ts[:, :3, :3], Ts[:, :3, 3], Ts[:, 3, 3] = Rs, Ps, 1.0
        path = [q]
        while len(path) <= n:
            for q_next in self.ik.refine_line(Ts[len(path) - 1:], path[-1]):
                self._check_jump(q_next, path[-1], len(path) - 1, n)
                path.append(q_next)
            if len(path) <= n:
                path.append(self._full_ik(Ts[len(path) - 1], path[-1], len(path) - 1, n, dist))
        return np.asarray(path)

    def _full_ik(self, T: np.ndarray, q_prev: np.ndarray, k: int, n: int, dist: float) -> np.ndarray:
        try:
            sols = self.ik.solve_flange(T, q_prev).solutions
        except UnreachablePoseError as exc:
            raise CartesianPathError(
                f"Cartesian line leaves the reachable workspace at step {k + 1}/{n} "
                f"({dist * 1e3:.0f} mm line): {exc}") from None
        q_next = sols[int(np.argmin(np.max(np.abs(sols - q_prev), axis=1)))]
        self._check_jump(q_next, q_prev, k, n)
        return q_next

    def _check_jump(self, q_next: np.ndarray, q_prev: np.ndarray, k: int, n: int) -> None:
        cfg = self.config
        jump = float(np.max(np.abs(q_next - q_prev)))
        if jump > cfg.cartesian_max_joint_step_rad:
            j = int(np.argmax(np.abs(q_next - q_prev)))
            raise CartesianPathError(
                f"Cartesian line needs a joint jump at step {k + 1}/{n}: joint {j + 1} changes by "
                f"{jump:.3f} rad (limit {cfg.cartesian_max_joint_step_rad} rad per "
                f"{cfg.cartesian_step_m * 1e3:.0f} mm step) — near a singularity or a joint limit")
