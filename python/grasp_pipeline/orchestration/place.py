"""PLACE (ours) and the recovery after a failed stage, as parts of the grasp action.

PLACE: straight up to the carry height (the planner does not model the object in the hand,
so it first hangs well above its neighbours), carry above one of the tray's drop slots
(fingers closing along world x there, clear of the tray walls), lower until the object's
bottom is ``place_clearance_m`` above the tray floor, open a little beyond the object, go
up, return to the start joints. A drop while carrying fails PLACE.

Recovery: open, retreat upward (or escape straight up when a retreat cannot start inside a
clearance), go home; each step best-effort, the arm is never left moving.
"""

from __future__ import annotations

import logging

import numpy as np

from ..exceptions import GraspPipelineError
from ..motion.exceptions import MotionError
from ..robot.description import GRIPPER_MAX_WIDTH_M
from ..robot.protocols import ContactAllowance
from ..results import GraspOutcome
from .gripper_moves import ObjectDropped
from .runtime import wait_s

log = logging.getLogger("grasp_pipeline.grasp")

HELD = ContactAllowance.HELD_OBJECT
FINGERS = ContactAllowance.FINGERS


def tray_slot(k: int, dx_m: float, dy_m: float) -> np.ndarray:
    """Offset of the k-th drop slot from the tray centre: a 2 x 3 grid, then round again."""
    k = k % 6
    return np.array([dx_m * (1 if k % 2 == 0 else -1), dy_m * (k // 2 - 1), 0.0])


def arrival_height_m(action) -> float:
    """TCP height [m] above the tray floor when arriving over a slot: ``place_height_m``, or
    higher so that the held object's bottom — hanging as far below the TCP as the TCP stood
    above the table at the grasp — clears the floor by ``place_hang_clearance_m``."""
    cfg = action.config
    hang_m = action.tcp_height_m or 0.0
    return max(cfg.place_height_m, hang_m + cfg.place_hang_clearance_m)


def _carry_up(action, out: GraspOutcome, plane_z_m: float):
    cfg, robot, motion = action.config, action.robot, action.motion
    T_up = robot.tcp_pose().copy()
    if T_up[2, 3] >= plane_z_m + cfg.carry_height_m:
        return
    T_up[2, 3] = plane_z_m + cfg.carry_height_m
    try:
        yield from action.carrying(motion.line(T_up, kind="carry_up", allow_target_contact=True,
                                               allowance=HELD), out, "PLACE")
    except ObjectDropped:
        raise
    except GraspPipelineError as exc:  # e.g. a wrist joint near a singularity on the line
        log.warning("carry_up line not plannable (%s); planning a joint-space motion to the "
                    "same pose instead", exc)
        motion.sync()
        yield from action.carrying(motion.to_pose(T_up, frame="tcp", kind="carry_up",
                                                  allowance=HELD), out, "PLACE")


def _lower(action, out: GraspOutcome, T_above: np.ndarray, slot: np.ndarray):
    cfg, motion = action.config, action.motion
    if action._target_height_m is None or action.tcp_height_m is None:
        return
    # the object's bottom hangs as far below the TCP as the TCP stood above the table
    z_release = cfg.place_clearance_m + action.tcp_height_m
    if z_release >= arrival_height_m(action):
        return
    T_down = T_above.copy()
    T_down[2, 3] = slot[2] + z_release
    try:
        yield from action.carrying(motion.line(T_down, kind="place_down", allowance=HELD), out, "PLACE")
    except ObjectDropped as exc:  # pushed out of the fingers by what lies in the tray: released
        log.warning("the object left the fingers while being lowered into the tray (%s); "
                    "it is released there", exc)
        motion.sync()
    except GraspPipelineError as exc:  # a crowded tray: release from above instead
        log.warning("could not lower the object into the tray (%s); releasing %.0f mm above "
                    "its floor", exc, (action.robot.tcp_pose()[2, 3] - slot[2]) * 1e3)
        motion.sync()


def place_orientations(R_hold: np.ndarray) -> list:
    """TCP rotations to place with: the held orientation turned about the world vertical —
    the object keeps the attitude it had on the table (it stood stably so), only its yaw
    changes. First the smallest turn that brings the closing axis over world x (the tray's
    slots leave room for the fingers along x: a top-down grasp then closes along x, as it
    always did), then that turn + 180°, ±45°, ±90°, ±135°."""
    R_hold = np.asarray(R_hold, dtype=float)
    y = R_hold[:2, 1]
    phi = float(np.arctan2(y[1], y[0])) if float(np.hypot(*y)) > 1e-6 else 0.0
    base = -phi if abs(phi) <= np.pi / 2 else np.pi - phi  # onto +x or -x, whichever is nearer
    base = (base + np.pi) % (2.0 * np.pi) - np.pi
    out = []
    for extra in np.radians([0.0, 180.0, 45.0, -45.0, 90.0, -90.0, 135.0, -135.0]):
        c, s = np.cos(base + extra), np.sin(base + extra)
        out.append(np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]) @ R_hold)
    return out


def _arrive(action, out: GraspOutcome, slot: np.ndarray):
    """Task: carry the object above ``slot`` (orientations of :func:`place_orientations`,
    then a lower arrival when the higher one is out of reach); returns the pose reached."""
    cfg, robot, motion = action.config, action.robot, action.motion
    errors = []
    heights = sorted({arrival_height_m(action), cfg.place_height_m}, reverse=True)
    for R in place_orientations(robot.tcp_pose()[:3, :3]):
        for z in heights:
            T_above = np.eye(4)
            T_above[:3, :3], T_above[:3, 3] = R, slot + np.array([0.0, 0.0, z])
            try:
                traj = motion.plan_pose(T_above)
            except MotionError as exc:  # far slots are near the arm's reach
                errors.append(str(exc))
                continue
            yield from action.carrying(motion.execute("place", traj, HELD), out, "PLACE")
            return T_above
    raise PlacePlanningError("no way to carry the object above the tray slot: " + " | ".join(errors[:4]))


class PlacePlanningError(GraspPipelineError):
    """No orientation or height above the tray slot could be planned."""


def place_in_tray(action, out: GraspOutcome):
    """Task: the PLACE stage of ``action`` (a :class:`~.grasp_action.GraspAction`)."""
    cfg, robot, motion = action.config, action.robot, action.motion
    cell = action.work_cell
    slot = cell.tray_center_m + tray_slot(action.placed_count, cfg.place_slot_dx_m, cfg.place_slot_dy_m)
    motion.set_touchable(None)
    plane = action.loop.plane
    yield from _carry_up(action, out, plane.height_m if plane is not None else float(slot[2]))
    T_above = yield from _arrive(action, out, slot)
    yield from _lower(action, out, T_above, slot)
    out.release_time_s = float(robot.time_s)
    # Open only a little beyond the object: fully open fingers could reach the tray walls.
    release_gap = min(GRIPPER_MAX_WIDTH_M, (out.stall_gap_m or 0.0) + cfg.open_margin_m)
    robot.set_gripper(release_gap, effort_N=cfg.close_effort_N)
    yield from wait_s(robot, cfg.release_wait_s)
    _release_in_world(action)
    action.placed_count += 1
    motion.planner.set_finger_opening(max(release_gap, robot.finger_gap_m))
    yield from _leave_tray(action, T_above)


def _leave_tray(action, T_above: np.ndarray):
    """Task: up out of the tray and home. The tray's contents are not perceived, so the hand
    may brush what lies there on the way up: contacts present when a motion starts and the
    fingers' contacts with objects do not stop it; the palm meeting something new does."""
    cfg, robot, motion = action.config, action.robot, action.motion
    if float(np.linalg.norm(robot.tcp_pose()[:3, 3] - T_above[:3, 3])) > cfg.gripper_goal_tolerance_m:
        try:
            yield from motion.line(T_above, kind="place_up", allowance=FINGERS, release_contacts=True)
        except GraspPipelineError as exc:
            log.warning("place_up not plannable (%s); escaping straight up", exc)
            motion.sync()
            yield from motion.escape_up(T_above[2, 3] - robot.tcp_pose()[2, 3], allowance=FINGERS)
    if action.home_q is not None:
        yield from motion.to_joints(action.home_q, kind="home", allowance=FINGERS, release_contacts=True)


def _retreat(action):
    cfg, robot, motion = action.config, action.robot, action.motion
    try:
        n = np.asarray(action.loop.plane.n if action.loop.plane is not None else [0, 0, 1.0])
        T = robot.tcp_pose().copy()
        T[:3, 3] += cfg.retreat_height_m * n
        yield from motion.line(T, kind="retreat", allow_target_contact=True, allowance=FINGERS,
                               release_contacts=True)
    except GraspPipelineError as exc:
        log.warning("retreat not plannable (%s); escaping straight up", exc)
        motion.sync()
        try:
            yield from motion.escape_up(cfg.retreat_height_m)
        except GraspPipelineError as exc2:
            log.warning("escape failed: %s", exc2)
            motion.sync()


def _release_in_world(action) -> None:
    """The planner's world after opening: the hand holds nothing any more."""
    action.motion.detach()


def recover(action):
    """Task: open, retreat upward, go home (best effort)."""
    cfg, robot, motion = action.config, action.robot, action.motion
    robot.set_gripper(GRIPPER_MAX_WIDTH_M, effort_N=cfg.close_effort_N)
    motion.sync()
    yield from wait_s(robot, cfg.release_wait_s)
    _release_in_world(action)
    motion.planner.set_finger_opening(GRIPPER_MAX_WIDTH_M)
    yield from _retreat(action)
    if action.home_q is not None:
        try:
            yield from motion.to_joints(action.home_q, kind="home", release_contacts=True)
        except GraspPipelineError as exc:
            log.warning("return home failed: %s", exc)
            motion.sync()
