"""PLACE (ours) and the recovery after a failed stage, as parts of the grasp action.

PLACE (parameters: ``config/place.yaml``):

1. straight up to ``carry_height_m`` above the table;
2. choose where the object goes: free spots of the tray, nearest the preferred ones
   (:mod:`.tray_spots`, on the tray's contents as the robot knows them, :mod:`.tray`);
3. carry the object above a spot — the attitude it was held with, turned about the vertical
   (:func:`place_orientations`) — the next rotation or spot when that cannot be planned (the
   held object is part of the planner's world, so the carry goes around what it would sweep).
   It arrives as high as it was carried — above the first spot where the arm reaches that —
   so that it crosses the tray's walls high and only goes down inside the tray (an object that
   turned in the fingers since it was grasped hangs lower than the planner's model of it);
   lower only where no spot can be reached so high;
4. lower it until its bottom is ``release_clearance_m`` above what is under it, or as far as
   the planner lets the line go; where it stops the straight line higher (a wrist singularity
   on the way down), a joint-space motion to the same low pose, if one can be planned (the
   held object is in the planner's world). It is never released higher than ``release_max_drop_m`` above
   what is under it: a lowering that stops higher (refused by the planner, or stopped by a
   contact, a tracking error or a settle timeout) backs up and tries the next spot, up to
   ``lower_attempts`` spots, then PLACE fails — except a touchdown: a lowering stopped by a
   tracking error or no settling with the hand held at least ``touch_down_m`` above its
   commanded height rests the object on what is under it (it hangs lower than the planner's
   model of it: turned in the fingers, or a part the camera never saw), and it is released
   there;
5. open a little beyond the object; the planner's world detaches it; it becomes the named
   obstacle ``placed/<k>`` where and how high it was released;
6. up, then look into the tray (:mod:`.tray_check`): the tray's contents are refreshed from
   what the camera sees, and the robot's verdict "placed" needs the new object seen there
   (PLACE fails otherwise); back to the start joints.

A drop while carrying fails PLACE. Recovery: open, retreat upward (or escape straight up when a
retreat cannot start inside a clearance), go home; each step best-effort, the arm is never left
moving.
"""

from __future__ import annotations

import logging
from typing import Optional

import numpy as np

from ...exceptions import GraspPipelineError
from ...motion.exceptions import MotionError
from ...motion.occupancy import cleared_cell_m
from ...motion.planning_world import held_spheres_in_tcp
from ...motion.robot_spheres import hand_spheres_in_tcp
from ...results import GraspOutcome
from ...robot.description import GRIPPER_MAX_WIDTH_M
from ...robot.protocols import ContactAllowance
from ..runtime import wait_s
from .gripper_moves import ObjectDropped
from .stages import Stage
from .tray import TrayContents, TrayGeometry
from .tray_check import PlaceNotSeen, arrival_verdict, look_into_tray
from .tray_spots import HeldShape, Spot, free_spots, preferred_positions

log = logging.getLogger("grasp_pipeline.grasp")

HELD = ContactAllowance.HELD_OBJECT
FINGERS = ContactAllowance.FINGERS
#: The preferred positions lie this far in from the edges of the tray floor [m].
PREFERRED_INSET_M = 0.055
#: After a release, the TCP goes at least this far above the released object's top [m].
CLEAR_ABOVE_M = 0.06
#: Stops of a lowering that say the arm could not follow (a touchdown shows as one of these;
#: a robot contact is its own reason and never counts as the object resting).
_HELD_UP_REASONS = ("tracking", "settle")


class PlacePlanningError(GraspPipelineError):
    """The object could not be carried above, or lowered into, any free spot of the tray."""


def place_orientations(R_hold: np.ndarray) -> list:
    """TCP rotations to place with: the held orientation turned about the world vertical —
    the object keeps the attitude it had on the table (it stood stably so), only its yaw
    changes. First the smallest turn that brings the closing axis over world x, then that
    turn + 180°, ±45°, ±90°, ±135°."""
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


def tray_contents(action) -> TrayContents:
    """The action's record of the tray (created at its first place)."""
    if action.tray is None:
        planner = action.motion.planner
        action.tray = TrayContents(TrayGeometry.from_work_cell(action.work_cell),
                                   cleared_cell_m(planner.config.voxel_size_m),
                                   action.place_config.seen_min_height_m)
    return action.tray


def release_gap_m(action, out: GraspOutcome) -> float:
    """The finger gap to release with: a little beyond the object (fully open fingers could
    reach the tray's walls or its contents)."""
    return min(GRIPPER_MAX_WIDTH_M, (out.stall_gap_m or 0.0) + action.config.open_margin_m)


def held_shape(action, out: GraspOutcome) -> HeldShape:
    """The held object's points and the planner's spheres of it and of the hand (fingers at
    the release gap), in the TCP frame; without perceived points, a box between the fingers
    as deep as the TCP stood above the table."""
    pts = action.held_points_tcp
    if pts is None or not len(pts):
        gap = max(out.stall_gap_m or 0.0, 0.01)
        depth = max(action.tcp_height_m or 0.0, 0.02)
        g = np.linspace(-0.5, 0.5, 5)
        X, Y, Z = np.meshgrid(0.04 * g, gap * g, depth * (g + 0.5))
        pts = np.c_[X.ravel(), Y.ravel(), Z.ravel()]
    planner = action.motion.planner
    pts = np.asarray(pts, float)
    oc, orad = held_spheres_in_tcp(planner.model, pts)
    c, r = hand_spheres_in_tcp(planner.model, planner.config.sphere_cell_m, release_gap_m(action, out))
    return HeldShape(pts, oc, orad, c, r)


def _carry_up(action, out: GraspOutcome, plane_z_m: float):
    """Task: straight up to ``carry_height_m`` above the table (a joint-space motion to that
    pose when the line cannot be followed); when that pose is out of reach, the carry starts
    from where the arm is — the planner knows the held object."""
    cfg, robot, motion = action.place_config, action.robot, action.motion
    T_up = robot.tcp_pose().copy()
    if T_up[2, 3] >= plane_z_m + cfg.carry_height_m:
        return
    T_up[2, 3] = plane_z_m + cfg.carry_height_m
    try:
        yield from action.carrying(motion.line(T_up, kind="carry_up", allow_target_contact=True,
                                               allowance=HELD), out, Stage.PLACE)
        return
    except ObjectDropped:
        raise
    except GraspPipelineError as exc:  # e.g. a wrist joint near a singularity on the line
        log.warning("carry_up line not plannable (%s); planning a joint-space motion to the "
                    "same pose instead", exc)
        motion.sync()
    try:
        traj = motion.plan_pose(T_up)
    except MotionError as exc:  # e.g. far from the base, a tilted grasp's pose up there
        log.warning("the pose above the grasp is out of reach (%s); carrying from here", exc)
        return
    yield from action.carrying(motion.execute("carry_up", traj, HELD), out, Stage.PLACE)


def _support_z_m(tray: TrayContents, shape: HeldShape, T: np.ndarray) -> float:
    """World height of what lies under the held object at the TCP pose ``T`` (the floor, or
    the top of the contents under its footprint)."""
    grid = tray.geometry.grid(tray.cell_m)
    ij = grid.index((shape.points_tcp @ T[:3, :3].T + T[:3, 3])[:, :2])
    ok = grid.inside(ij)
    under = tray.heights(grid)[ij[ok, 0], ij[ok, 1]]
    return tray.geometry.floor_z_m + (float(under.max()) if len(under) else 0.0)


def _arrival_heights(action, shape: HeldShape, R: np.ndarray, carry_z_m: Optional[float]) -> list:
    """TCP heights (world z) to arrive at over a spot, highest first: with ``carry_z_m`` (the
    height it was carried at) that one alone, if the object's bottom clears the walls and
    contents there; else ``arrival_height_m`` above the floor, or higher so that the object's
    bottom clears them by ``hang_clearance_m``, then that lowest clearing height."""
    cfg, tray = action.place_config, tray_contents(action)
    top = max(tray.geometry.rim_m, float(tray.heights(tray.geometry.grid(cfg.spot_cell_m)).max()))
    low = shape.bottom_m(R) + top + cfg.hang_clearance_m
    floor_z = tray.geometry.floor_z_m
    if carry_z_m is not None:
        return [carry_z_m] if carry_z_m >= floor_z + low else []
    return sorted({floor_z + max(cfg.arrival_height_m, low), floor_z + low}, reverse=True)


def _arrive(action, out: GraspOutcome, spot: Spot, shape: HeldShape, errors: list,
            carry_z_m: Optional[float]):
    """Task: carry the object above ``spot`` (its free rotations, each at the arrival heights
    of :func:`_arrival_heights`); returns the pose reached, or None when none can be planned
    (reasons added to ``errors``)."""
    motion = action.motion
    for R in spot.rotations:
        for z in _arrival_heights(action, shape, R, carry_z_m):
            T = np.eye(4)
            T[:3, :3], T[:3, 3] = R, [spot.xy[0], spot.xy[1], z]
            try:
                traj = motion.plan_pose(T)
            except MotionError as exc:  # far spots are near the arm's reach
                errors.append(str(exc))
                continue
            yield from action.carrying(motion.execute("place", traj, HELD), out, Stage.PLACE)
            return T
    return None


def lowest_line(motion, T_above: np.ndarray, z_goal_m: float, step_m: float):
    """(trajectory, z reached, why not lower) of the straight TCP line down from ``T_above``
    to ``z_goal_m``, or of its lowest part the planner accepts (bisection to ``step_m``);
    the trajectory is None when no part of it can be planned."""
    T = np.asarray(T_above, float).copy()
    T[2, 3] = z_goal_m
    try:
        return motion.plan_line(T), z_goal_m, ""
    except MotionError as exc:
        why = str(exc)
    lo, hi, best = z_goal_m, float(T_above[2, 3]), None
    while hi - lo > step_m:
        T[2, 3] = mid = 0.5 * (lo + hi)
        try:
            best, hi = motion.plan_line(T), mid
        except MotionError:
            lo = mid
    return best, hi, why


def _lower(action, out: GraspOutcome, T_above: np.ndarray, shape: HeldShape, notes: list):
    """Task: lower the object at ``T_above``'s spot (module doc, step 4). True: it is low
    enough to release (or already left the fingers); False: it stopped high (the arm is back
    up) — why in ``notes``."""
    cfg, robot, motion = action.place_config, action.robot, action.motion
    tray = tray_contents(action)
    bottom = shape.bottom_m(T_above[:3, :3])
    support = _support_z_m(tray, shape, T_above)
    z_goal = support + cfg.release_clearance_m + bottom
    traj, z_low, why = lowest_line(motion, T_above, z_goal, cfg.lower_step_m)
    where = f"({T_above[0, 3]:.3f}, {T_above[1, 3]:.3f})"
    if z_low - bottom - support > cfg.release_max_drop_m:
        traj, z_low, why = _lower_in_joint_space(motion, T_above, z_goal, (traj, z_low, why),
                                                 f"at {where} the straight line stops "
                                                 f"{(z_low - bottom - support) * 1e3:.0f} mm up")
    if z_low - bottom - support > cfg.release_max_drop_m:
        notes.append(f"at {where} the planner stops the lowering {(z_low - bottom - support) * 1e3:.0f} "
                     f"mm above what is under the object ({why})")
        log.warning("lowering into the tray: %s; trying elsewhere", notes[-1])
        return False
    log.info("lowering at %s to %.0f mm above what is under the object", where,
             (z_low - bottom - support) * 1e3)
    if traj is None:
        return True
    try:
        yield from action.carrying(motion.execute("place_down", traj, HELD), out, Stage.PLACE)
    except ObjectDropped as exc:  # pushed out of the fingers by what lies in the tray: released
        log.warning("the object left the fingers while being lowered into the tray (%s); it is "
                    "released there", exc)
        motion.sync()
    except MotionError as exc:  # a contact, a tracking error, no settling
        motion.sync()
        drop = float(robot.tcp_pose()[2, 3]) - bottom - support
        held_up = hand_held_up_m(motion.planner, exc)
        if held_up >= cfg.touch_down_m:
            log.info("the lowering stopped with the hand held %.0f mm above its command: the object "
                     "rests on what is under it (the model put it %.0f mm higher); releasing there",
                     held_up * 1e3, drop * 1e3)
            return True
        if drop > cfg.release_max_drop_m:
            notes.append(f"at {where} the lowering stopped {drop * 1e3:.0f} mm above what is under "
                         f"the object ({exc})")
            log.warning("lowering into the tray: %s; backing up to try elsewhere", notes[-1])
            yield from _back_up(action, out)
            return False
        log.info("the lowering stopped %.0f mm above what is under the object (%s); releasing "
                 "there", drop * 1e3, exc)
    return True


def _lower_in_joint_space(motion, T_above: np.ndarray, z_goal_m: float, line: tuple, where: str) -> tuple:
    """(trajectory, z reached, why not lower) of a joint-space motion from ``T_above`` down to
    ``z_goal_m`` — where the straight line crosses a wrist singularity on the way down; the
    line's ``(trajectory, z, why)`` when that cannot be planned either."""
    T_low = np.asarray(T_above, float).copy()
    T_low[2, 3] = z_goal_m
    try:
        traj = motion.plan_pose(T_low)
    except MotionError as exc:
        return line[0], line[1], f"{line[2]}; joint-space: {exc}"
    log.info("lowering: %s (%s); a joint-space motion instead", where, line[2])
    return traj, z_goal_m, ""


def hand_held_up_m(planner, exc: Exception) -> float:
    """How far above its commanded height the TCP stood when the motion ``exc`` stopped it
    (the arm held up by what the lowered object rests on: a touchdown); 0 when the stop did
    not come from following the arm (a contact of the robot itself, or no joints known)."""
    q_commanded = getattr(exc, "q_commanded", None)
    q_measured = getattr(exc, "q_measured", None)
    if q_commanded is None or q_measured is None or getattr(exc, "reason", "") not in _HELD_UP_REASONS:
        return 0.0
    return float(planner.ik.fk_tcp(q_measured)[2, 3] - planner.ik.fk_tcp(q_commanded)[2, 3])


def _back_up(action, out: GraspOutcome):
    """Task: up by ``lower_backoff_m`` from a stopped lowering, still holding the object."""
    motion = action.motion
    T = action.robot.tcp_pose().copy()
    T[2, 3] += action.place_config.lower_backoff_m
    try:
        yield from action.carrying(motion.line(T, kind="place_back_up", allowance=HELD,
                                               release_contacts=True), out, Stage.PLACE)
    except ObjectDropped:
        raise
    except GraspPipelineError as exc:
        log.warning("backing up not plannable (%s); escaping straight up", exc)
        motion.sync()
        yield from action.carrying(motion.escape_up(action.place_config.lower_backoff_m,
                                                    kind="place_back_up", allowance=HELD),
                                   out, Stage.PLACE)


def _put_down(action, out: GraspOutcome, spots: list, shape: HeldShape):
    """Task: arrive above the spots in turn and lower the object at them until one lets it go
    down low; returns (spot, pose above it)."""
    cfg = action.place_config
    errors, notes, lowered = [], [], set()
    carry_z = float(action.robot.tcp_pose()[2, 3])  # the height it is carried at
    for height in (carry_z, None):  # as high as it was carried above any spot first
        for k, spot in enumerate(spots):
            if k in lowered or len(lowered) >= cfg.lower_attempts:
                continue
            T_above = yield from _arrive(action, out, spot, shape, errors, height)
            if T_above is None:
                continue
            if (yield from _lower(action, out, T_above, shape, notes)):
                return spot, T_above
            lowered.add(k)
    if notes:
        raise PlacePlanningError(f"could not lower the object to within "
                                 f"{cfg.release_max_drop_m * 1e3:.0f} mm of what lies under it at "
                                 f"{len(lowered)} spot(s) of the tray: " + " | ".join(notes))
    raise PlacePlanningError(f"no way to carry the object above any of {len(spots)} free spot(s) "
                             "of the tray: " + " | ".join(errors[:4]))


def _release(action, out: GraspOutcome, shape: HeldShape) -> np.ndarray:
    """Task: open a little beyond the object and let it go; returns its points (world) at
    the release pose."""
    robot, cfg = action.robot, action.config
    out.release_time_s = float(robot.time_s)
    gap = release_gap_m(action, out)
    robot.set_gripper(gap, effort_N=cfg.close_effort_N)
    T = robot.tcp_pose()
    yield from wait_s(robot, cfg.release_wait_s)
    _release_in_world(action)
    action.placed_count += 1
    action.motion.planner.set_finger_opening(max(gap, robot.finger_gap_m))
    return shape.points_tcp @ T[:3, :3].T + T[:3, 3]


def _sync_obstacles(action, gone: list) -> None:
    """The planner's world gets the tray's contents as they are known now."""
    tray, motion = tray_contents(action), action.motion
    for name in gone:
        motion.remove_obstacle(name)
    for obj in tray.objects.values():
        motion.add_obstacle(obj.name, obj.box(tray.geometry.floor_z_m), obj.tops)


def _rise_clear_of(action, top_z_m: float):
    """Task: when the hand lies within the clearance of what was just released (it left the
    fingers early, e.g. pushed out while being lowered, and the hand is still at it), straight
    up until the TCP is ``CLEAR_ABOVE_M`` above its top: the following motions start valid."""
    motion = action.motion
    rise = top_z_m + CLEAR_ABOVE_M - float(action.robot.tcp_pose()[2, 3])
    if rise <= 0 or motion.planner.validator.is_valid(motion.q_cmd):
        return
    log.info("the hand is within the clearance of the released object; up %.0f mm first", rise * 1e3)
    try:
        yield from motion.escape_up(rise, kind="place_up", allowance=FINGERS)
    except GraspPipelineError as exc:
        log.warning("could not rise clear of the released object: %s", exc)
        motion.sync()


def _check_arrival(action, released_world: np.ndarray, spot: Spot):
    """Task: register the released object, look into the tray, refresh the contents; raises
    :class:`PlaceNotSeen` when the object is not seen there."""
    tray = tray_contents(action)
    grid = tray.geometry.grid(tray.cell_m)
    before = tray.heights(grid)
    obj = tray.add_released(released_world)
    _sync_obstacles(action, [])
    yield from _rise_clear_of(action, float(obj.tops[:, 2].max()))
    footprint = tray.heights(grid) > before
    if not np.any(footprint):  # the object's model lies outside the tray's grid
        footprint = np.zeros(grid.shape, dtype=bool)
        ij = grid.index(spot.xy[None])[0]
        footprint[tuple(np.clip(ij, 0, np.array(grid.shape) - 1))] = True
    top = float(tray.heights(grid).max())
    points = yield from look_into_tray(action, tray.geometry.center_xy, top)
    top = float(obj.tops[:, 2].max()) + 0.5 * tray.cell_m - tray.geometry.floor_z_m
    verdict = arrival_verdict(grid, before, footprint, top, points, action.place_config)
    if points is not None:
        _sync_obstacles(action, tray.update_from_look(points))
    log.info("tray look after placing %s: %s", obj.name, verdict.message)
    if not verdict.placed:
        raise PlaceNotSeen(verdict.message)


def place_in_tray(action, out: GraspOutcome):
    """Task: the PLACE stage of ``action`` (a :class:`~.grasp_action.GraspAction`)."""
    motion = action.motion
    tray = tray_contents(action)
    motion.set_touchable(None)
    trimmed = motion.trim_held()
    if trimmed:
        log.warning("the held object's model lay inside %d obstacle sphere(s) where the hand holds "
                    "it now: those parts (filled in under what was seen) are dropped", trimmed)
    plane = action.loop.plane
    yield from _carry_up(action, out, plane.height_m if plane is not None else tray.geometry.floor_z_m)
    shape = held_shape(action, out)
    R_held = action.robot.tcp_pose()[:3, :3]
    spots = free_spots(tray, shape, place_orientations(R_held),
                       preferred_positions(tray.geometry, action.placed_count, PREFERRED_INSET_M),
                       action.place_config)
    log.info("tray: %d object(s) in it; %d free spot(s) for the held object (%s), the first at "
             "(%.3f, %.3f)", len(tray.objects), len(spots), shape.size_mm(), *spots[0].xy)
    spot, T_above = yield from _put_down(action, out, spots, shape)
    released = yield from _release(action, out, shape)
    yield from _leave_tray(action, T_above)
    yield from _check_arrival(action, released, spot)
    if action.home_q is not None:
        yield from motion.to_joints(action.home_q, kind="home", allowance=FINGERS, release_contacts=True)


def _leave_tray(action, T_above: np.ndarray):
    """Task: straight up out of the tray. Contacts present when the motion starts and the
    fingers' contacts with objects do not stop it; the palm meeting something new does."""
    cfg, robot, motion = action.config, action.robot, action.motion
    if float(np.linalg.norm(robot.tcp_pose()[:3, 3] - T_above[:3, 3])) <= cfg.gripper_goal_tolerance_m:
        return
    try:
        yield from motion.line(T_above, kind="place_up", allowance=FINGERS, release_contacts=True)
    except GraspPipelineError as exc:
        log.warning("place_up not plannable (%s); escaping straight up", exc)
        motion.sync()
        yield from motion.escape_up(T_above[2, 3] - robot.tcp_pose()[2, 3], allowance=FINGERS)


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
