"""Gripper routines of the grasp action as runtime task generators (method.md §7).

Everything here reads only the :class:`~grasp_pipeline.robot.protocols.Gripper` signals
(measured gap, finger speed, squeeze force) and the clock — never simulator contacts:

* :func:`wait_gap` — wait until the measured gap is within tolerance of a target;
* :func:`close_until_stall` — close on an object until the fingers *stall* (speed below
  ``stall_speed_mps`` for ``stall_time_s``, or — ours — the gap held within
  ``stall_gap_band_m`` for ``stall_time_s``: pads pressing a thin or light object chatter,
  and their speed reading jumps above the threshold while the gap stands still); reaching the
  commanded gap, closing fully or stalling without force means nothing is held; once
  stalled (``hold_by_force``) the fingers are commanded shut at the same effort, so the squeeze
  stays ``close_effort_N`` while the object creeps between the pads, as a force-controlled
  hand (the Franka Hand's grasp) holds;
* :func:`watch_held` — wrap a motion so that a drop (:func:`hold_lost`: the fingers shut
  below ``fully_closed_gap_m``, or the gap fell ``held_gap_drop_m`` below the stall gap *and*
  the squeeze force fell below ``held_min_force_N``) aborts it at once.
"""

from __future__ import annotations

import logging

from collections import deque

from ...exceptions import GraspPipelineError
from ..config import GraspConfig

log = logging.getLogger("grasp_pipeline.grasp")


class StageFailure(GraspPipelineError):
    """A grasp stage could not complete (the message says why)."""


class ObjectDropped(StageFailure):
    """The held object left the fingers (the gap closed below the stall gap)."""


def wait_gap(robot, gap_m: float, config: GraspConfig):
    """Task: wait until the finger gap is ``gap_m`` ± ``gripper_goal_tolerance_m``."""
    t_end = robot.time_s + config.close_timeout_s
    while abs(robot.finger_gap_m - gap_m) > config.gripper_goal_tolerance_m:
        if robot.time_s >= t_end:
            raise StageFailure(f"gripper did not reach {gap_m * 1e3:.1f} mm "
                               f"(at {robot.finger_gap_m * 1e3:.1f} mm)")
        yield


def close_command_m(width_m: float, config: GraspConfig) -> float:
    """The commanded gap when closing on an object ``width_m`` wide (narrower: it stalls)."""
    return max(0.0, 2.0 * config.close_command_fraction * width_m - config.close_squeeze_m)


class StallWatch:
    """Whether the closing fingers have stalled, from the gripper's gap and speed readings.

    method.md §7: speed below ``stall_speed_mps`` for ``stall_time_s``. Ours: also when the gap
    stayed within ``stall_gap_band_m`` over the last ``stall_time_s`` — a still gap whose speed
    reading chatters. Neither counts before ``stall_time_s`` has passed since the command."""

    def __init__(self, t0_s: float, config: GraspConfig):
        self.t0_s, self.config = t0_s, config
        self.slow_since: float | None = None
        self.gaps: deque = deque()  # (time [s], gap [m]): the last stall_time_s and one before

    def update(self, time_s: float, gap_m: float, speed_mps: float) -> bool:
        """Record one reading; True once stalled."""
        cfg = self.config
        self.gaps.append((time_s, gap_m))
        while len(self.gaps) > 1 and self.gaps[1][0] <= time_s - cfg.stall_time_s:
            self.gaps.popleft()
        if time_s - self.t0_s <= cfg.stall_time_s:
            return False
        if abs(speed_mps) < cfg.stall_speed_mps:
            self.slow_since = time_s if self.slow_since is None else self.slow_since
            if time_s - self.slow_since >= cfg.stall_time_s:
                return True
        else:
            self.slow_since = None
        return self._gap_still(time_s)

    def _gap_still(self, time_s: float) -> bool:
        if time_s - self.gaps[0][0] < self.config.stall_time_s:
            return False  # readings do not span the window yet
        gaps = [g for _, g in self.gaps]
        return max(gaps) - min(gaps) <= self.config.stall_gap_band_m


def close_until_stall(robot, width_m: float, config: GraspConfig):
    """Task: close on an object of ``width_m``; returns the stall gap [m]."""
    cmd = close_command_m(width_m, config)
    robot.set_gripper(cmd, effort_N=config.close_effort_N)
    t0 = robot.time_s
    watch = StallWatch(t0, config)
    while True:
        yield
        gap = robot.finger_gap_m
        if abs(gap - cmd) <= config.gripper_goal_tolerance_m:
            raise StageFailure(f"fingers reached the commanded {cmd * 1e3:.1f} mm without "
                               "stalling on the object (missed or much narrower)")
        if watch.update(robot.time_s, gap, robot.finger_speed_mps):
            break
        if robot.time_s - t0 > config.close_timeout_s:
            raise StageFailure(f"close timed out after {config.close_timeout_s} s "
                               f"(gap {gap * 1e3:.1f} mm)")
    stall_gap = _check_held(robot, width_m, config)
    if config.hold_by_force:
        robot.set_gripper(0.0, effort_N=config.close_effort_N)
    return stall_gap


def _check_held(robot, width_m: float, config: GraspConfig) -> float:
    gap, force = robot.finger_gap_m, max(0.0, robot.gripper_force_N)
    if gap < config.fully_closed_gap_m:
        raise StageFailure(f"gripper fully closed ({gap * 1e3:.1f} mm): missed the object")
    min_force = config.held_min_force_N
    if force < min_force:
        raise StageFailure(f"fingers stalled at {gap * 1e3:.1f} mm but squeeze only {force:.1f} N "
                           f"(< {min_force:.1f} N): nothing held between the pads")
    log.info("closed: stalled at %.1f mm, %.0f N (measured width %.1f mm)", gap * 1e3, force,
             width_m * 1e3)
    return gap


def hold_lost(robot, stall_gap_m: float, config: GraspConfig) -> bool:
    """Whether the gripper has lost the object it stalled on at ``stall_gap_m``: the fingers
    shut (gap below ``fully_closed_gap_m``: nothing between the pads), or the gap fell more
    than ``held_gap_drop_m`` below the stall gap and the squeeze force fell below
    ``held_min_force_N`` (the fingers no longer press on anything). A narrower gap at full
    force is still a hold: a rounded object turns a little between the pads and settles."""
    gap = robot.finger_gap_m
    if gap < config.fully_closed_gap_m:
        return True
    return (gap < stall_gap_m - config.held_gap_drop_m
            and robot.gripper_force_N < config.held_min_force_N)


def lost_message(robot, stall_gap_m: float, when: str) -> str:
    return (f"object {when}: finger gap fell from {stall_gap_m * 1e3:.1f} to "
            f"{robot.finger_gap_m * 1e3:.1f} mm, squeeze {max(0.0, robot.gripper_force_N):.1f} N")


def watch_held(robot, motion_gen, stall_gap_m: float, config: GraspConfig, stage: str):
    """Task: run ``motion_gen`` and raise :class:`ObjectDropped` as soon as
    :func:`hold_lost`; returns the motion's result."""
    while True:
        try:
            next(motion_gen)
        except StopIteration as done:
            return done.value
        if hold_lost(robot, stall_gap_m, config):
            motion_gen.close()  # the executor holds the arm where it is
            raise ObjectDropped(lost_message(robot, stall_gap_m, f"dropped during {stage}"))
        yield
