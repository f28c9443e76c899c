"""Gripper routines of the grasp action as runtime task generators (SPEC 7).

Everything here reads only the :class:`~grasp_pipeline.robot.protocols.Gripper` signals
(measured gap, finger speed, squeeze force) and the clock — never simulator contacts:

* :func:`wait_gap` — wait until the measured gap is within tolerance of a target;
* :func:`close_until_stall` — close on an object until the fingers *stall* (speed below
  ``stall_speed_mps`` for ``stall_time_s``); reaching the commanded gap, closing fully or
  stalling without force means nothing is held;
* :func:`watch_held` — wrap a motion so that a drop (:func:`hold_lost`: the gap fell
  ``held_gap_drop_m`` below the stall gap *and* the squeeze force fell below
  ``held_min_force_N``) aborts it at once.
"""

from __future__ import annotations

import logging

from ..exceptions import GraspPipelineError
from .config import GraspConfig

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


def _stalled(robot, t0_s: float, slow_since, config: GraspConfig):
    """(stalled now?, updated slow-since time)."""
    speed = abs(robot.finger_speed_mps)
    if speed < config.stall_speed_mps and robot.time_s - t0_s > config.stall_time_s:
        slow_since = robot.time_s if slow_since is None else slow_since
        return robot.time_s - slow_since >= config.stall_time_s, slow_since
    return False, None


def close_until_stall(robot, width_m: float, config: GraspConfig):
    """Task: close on an object of ``width_m``; returns the stall gap [m]."""
    cmd = close_command_m(width_m, config)
    robot.set_gripper(cmd, effort_N=config.close_effort_N)
    t0, slow_since = robot.time_s, None
    while True:
        yield
        gap = robot.finger_gap_m
        if abs(gap - cmd) <= config.gripper_goal_tolerance_m:
            raise StageFailure(f"fingers reached the commanded {cmd * 1e3:.1f} mm without "
                               "stalling on the object (missed or much narrower)")
        stalled, slow_since = _stalled(robot, t0, slow_since, config)
        if stalled:
            break
        if robot.time_s - t0 > config.close_timeout_s:
            raise StageFailure(f"close timed out after {config.close_timeout_s} s "
                               f"(gap {gap * 1e3:.1f} mm)")
    return _check_held(robot, width_m, config)


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
    """Whether the gripper has lost the object it stalled on at ``stall_gap_m``: the gap fell
    more than ``held_gap_drop_m`` below the stall gap and the squeeze force fell below
    ``held_min_force_N`` (the fingers no longer press on anything). A narrower gap at full
    force is still a hold: a rounded object turns a little between the pads and settles."""
    return (robot.finger_gap_m < stall_gap_m - config.held_gap_drop_m
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
