"""How wide a grasp may be: the one definition of the gripper's usable opening.

The hand opens at most to its largest finger gap, the robot's fact
(:data:`grasp_pipeline.robot.limits.GRIPPER_MAX_WIDTH_M`, 80 mm). Before approaching, the fingers
open to the grasp's width plus ``grasp.open_margin_m``, at most to that gap; a grasp keeps at
least ``grasp_fit.min_open_margin_m`` of the gap to spare. Hence

* :func:`max_grasp_width_m` — the *usable opening*: the widest grasp any grasp source may propose
  and the widest object the scan counts as one graspable object (its ``wide`` rule), the gap
  less ``grasp_fit.min_open_margin_m`` (72 mm by default);
* :func:`full_margin_width_m` — the widest grasp around which the fingers still open the whole
  ``grasp.open_margin_m`` (60 mm by default; wider grasps open by less, down to
  ``min_open_margin_m``). The top-down source's box heuristics model the fingers at the whole
  margin around the box — the perpendicular box grasp (:func:`~..scene.selection.perpendicular_grasp`)
  and the accessibility order (:mod:`.accessibility`) — and so take only boxes this narrow.
"""

from __future__ import annotations

from ...robot.limits import GRIPPER_MAX_WIDTH_M
from ..config import GraspConfig, GraspFitConfig


def max_grasp_width_m(fit: GraspFitConfig) -> float:
    """The usable opening [m]: the hand's largest opening less ``fit.min_open_margin_m``."""
    return GRIPPER_MAX_WIDTH_M - fit.min_open_margin_m


def full_margin_width_m(grasp: GraspConfig) -> float:
    """The widest grasp [m] the fingers open the whole ``grasp.open_margin_m`` around: the hand's
    largest opening less that margin."""
    return GRIPPER_MAX_WIDTH_M - grasp.open_margin_m
