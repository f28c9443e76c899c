"""Whether the whole arm reaches a grasp: inverse kinematics of its TCP pose and of its
pre-grasp pose, for the hand orientation(s) it allows, within the joint limits — and, with a
planning scene set for the target, collision-free (the planner's own validity checker).

A grasp whose closing axis has no chosen sign is tried with the hand orientation nearer the
reference TCP first (the one the planner would choose), then the other.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Optional

import numpy as np

from ...motion.exceptions import UnreachablePoseError
from ...motion.poses import rotation_angle
from .grasp import Grasp


def tcp_orientations(grasp: Grasp, reference_R: Optional[np.ndarray]) -> list:
    """The TCP rotations (x = c × a, y = ±c, z = a) to try for ``grasp``, best first."""
    if grasp.tcp_R is not None:
        return [grasp.tcp_R]
    a, c = grasp.approach, grasp.closing
    both = [np.column_stack([np.cross(s * c, a), s * c, a]) for s in (1.0, -1.0)]
    if reference_R is None:
        return both
    return sorted(both, key=lambda R: rotation_angle(R @ np.asarray(reference_R)[:3, :3].T))


#: Joint-7 samples of the reach check's IK (the planner itself uses ``ik_q7_samples``): enough
#: to find a solution where one exists, not to list them all.
Q7_SAMPLES = 8


class ArmReach:
    """A reach check bound to a planner (``MotionPlanner``) and the joints to start from.

    ``check_collisions``: also require a collision-free IK solution of the grasp (target
    contact allowed) and of the pre-grasp, in the planner's current scene (set it for the
    target first)."""

    def __init__(self, planner, q_ref: np.ndarray, reference_tcp: Optional[np.ndarray] = None,
                 check_collisions: bool = False, q7_samples: int = Q7_SAMPLES) -> None:
        self.planner = planner
        self.q_ref = np.asarray(q_ref, dtype=float)
        self.reference_tcp = reference_tcp
        self.check_collisions = check_collisions
        self.q7_samples = int(q7_samples)

    def _solutions(self, T: np.ndarray, q_seed: np.ndarray, allow_target: bool) -> np.ndarray:
        try:
            sols = self.planner.solve_ik(T, q_seed, "tcp", self.q7_samples).solutions
        except UnreachablePoseError:
            return np.zeros((0, 7))
        if not self.check_collisions or len(sols) == 0:
            return sols
        v = self.planner.validator
        prev = v.allow_target_contact
        v.allow_target_contact = allow_target
        try:
            return sols[v.check_batch(sols)]
        finally:
            v.allow_target_contact = prev

    def __call__(self, grasp: Grasp, pre_distance_m: float) -> Optional[Grasp]:
        """``grasp`` with the reachable TCP orientation chosen, or None."""
        for R in tcp_orientations(grasp, self.reference_tcp):
            T = np.eye(4)
            T[:3, :3], T[:3, 3] = R, grasp.position
            at = self._solutions(T, self.q_ref, True)
            if len(at) == 0:
                continue
            T_pre = T.copy()
            T_pre[:3, 3] -= pre_distance_m * grasp.approach
            if len(self._solutions(T_pre, at[0], False)):
                return replace(grasp, tcp_R=R)
        return None
