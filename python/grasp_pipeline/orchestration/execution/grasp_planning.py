"""Planning a grasp before any motion: PRE_GRASP and APPROACH for the first candidate that works.

For each candidate grasp (in the source's order) and each back-off (``approach_backoffs_m``:
the same grasp a little farther back along the approach, still within the finger pads' reach),
the TCP grasp pose is built (:func:`~grasp_pipeline.motion.grasp_poses.tcp_pose_from_grasp`:
the hand orientation the source chose, else the closing sign nearest the current hand); the
straight approach line from the pre-grasp ``pre_grasp_distance_m`` back along the approach is
planned backwards from the grasp pose (one IK branch), then the motion to the pre-grasp around
the perceived scene (:meth:`~.motion_client.MotionClient.plan_approach`). Nothing moves until a
pair is found. The grasp action and ``bench planning`` both use this.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from ...motion.exceptions import MotionError
from ...motion.grasp_poses import tcp_pose_from_grasp
from ...motion.trajectory import JointTrajectory
from ..config import GraspConfig

log = logging.getLogger("grasp_pipeline.grasp")


class NoReachableGrasp(MotionError):
    """No candidate grasp (with any back-off) can be planned; the message lists why each failed."""


@dataclass(frozen=True)
class PlannedGrasp:
    """A grasp whose motions are planned: the candidate, its index, the back-off [m], the
    pre-grasp and approach trajectories, and the TCP pose at the grasp (4x4)."""

    grasp: object
    index: int
    backoff_m: float
    pre_grasp: JointTrajectory
    approach: JointTrajectory
    T_grasp: np.ndarray

    @property
    def approach_axis(self) -> np.ndarray:
        return np.asarray(self.grasp.R, dtype=float)[:, 0]


def opening_for(grasp, config: GraspConfig, max_width_m: float) -> float:
    """Finger opening before approaching: the grasp's width + ``open_margin_m`` (≤ max)."""
    return min(max_width_m, float(grasp.width_m) + config.open_margin_m)


def grasp_tcp_poses(grasp, backoff_m: float, config: GraspConfig,
                    reference_tcp: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """TCP poses (4x4) at the grasp (backed off along the approach) and at the pre-grasp."""
    approach = np.asarray(grasp.R, dtype=float)[:, 0]
    T_grasp = tcp_pose_from_grasp(grasp, reference_tcp)
    T_grasp[:3, 3] -= backoff_m * approach
    T_pre = T_grasp.copy()
    T_pre[:3, 3] -= config.pre_grasp_distance_m * approach
    return T_grasp, T_pre


def plan_grasp(motion, candidates: list, config: GraspConfig, reference_tcp: np.ndarray,
               max_width_m: float) -> PlannedGrasp:
    """The first candidate × back-off whose approach and pre-grasp can both be planned
    (:meth:`~.motion_client.MotionClient.plan_approach`).

    ``motion``: the :class:`~.motion_client.MotionClient` (scene already set, target marked).
    Both motions are checked with the fingers at the grasp's opening: the grasp action sets
    the fingers to it before the arm moves (the opening the grasp source checked against the
    neighbours; fully open fingers left from the previous pick collided with piles at the
    pre-grasp). Raises :class:`NoReachableGrasp` listing every try's failure."""
    errors = []
    tries = [(k, g, b) for k, g in enumerate(candidates) for b in config.approach_backoffs_m]
    for n, (k, g, backoff) in enumerate(tries, start=1):
        T_grasp, T_pre = grasp_tcp_poses(g, backoff, config, reference_tcp)
        motion.planner.set_finger_opening(opening_for(g, config, max_width_m))
        try:
            traj_pre, traj_app = motion.plan_approach(T_grasp, T_pre)
        except MotionError as exc:
            errors.append(f"grasp {k + 1} (backoff {backoff * 1e3:.0f} mm): {exc}")
            log.info("grasp try %d of %d not plannable: %s", n, len(tries), exc)
            continue
        if n > 1:
            log.info("using grasp try %d: candidate %d, %.0f mm above the contact point",
                     n, k + 1, backoff * 1e3)
        return PlannedGrasp(g, k, backoff, traj_pre, traj_app, T_grasp)
    if not candidates:
        raise NoReachableGrasp("the grasp source proposed no grasp for this object")
    raise NoReachableGrasp("no grasp candidate can be reached: " + " | ".join(errors))
