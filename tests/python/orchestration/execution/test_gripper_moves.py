"""Closing until the fingers stall (method.md §7, and the still-gap rule of ours)."""

from __future__ import annotations

from dataclasses import replace

import pytest

from grasp_pipeline.orchestration.config import GraspConfig
from grasp_pipeline.orchestration.execution.gripper_moves import (StageFailure, StallWatch,
                                                                 close_command_m,
                                                                 close_until_stall, hold_lost)

STEP_S = 0.002


class ScriptedGripper:
    """Gripper readings from a script: the gap closes at ``close_speed_mps`` until it meets an
    object ``object_m`` wide, then holds it at ``force_N``; after contact the speed reading
    chatters with ``chatter_mps`` every ``chatter_every`` steps, the gap then reading
    ``jitter_m`` narrower, and the gap moves by ``creep_mps`` (a pad sliding along the object)."""

    def __init__(self, object_m: float, chatter_mps: float = 0.0, chatter_every: int = 50,
                 creep_mps: float = 0.0, close_speed_mps: float = 0.08, force_N: float = 40.0,
                 jitter_m: float = 0.0001):
        self.time_s, self.finger_gap_m, self.finger_speed_mps = 0.0, 0.036, 0.0
        self.gripper_force_N, self._force = 0.0, force_N
        self.object_m, self.chatter_mps, self.chatter_every = object_m, chatter_mps, chatter_every
        self.creep_mps, self.close_speed_mps, self._steps = creep_mps, close_speed_mps, 0
        self.jitter_m, self._held_gap_m = jitter_m, None

    def set_gripper(self, gap_m: float, effort_N: float) -> None:
        self.command_m, self.effort_N = gap_m, effort_N

    def step(self) -> None:
        self.time_s += STEP_S
        self._steps += 1
        if self.finger_gap_m > self.object_m:
            self.finger_gap_m = max(self.object_m, self.finger_gap_m - self.close_speed_mps * STEP_S)
            self.finger_speed_mps = -self.close_speed_mps
            return
        self.gripper_force_N = self._force
        held = self.finger_gap_m if self._held_gap_m is None else self._held_gap_m
        self._held_gap_m = held - self.creep_mps * STEP_S
        chatter = self._steps % self.chatter_every == 0
        self.finger_gap_m = self._held_gap_m - (self.jitter_m if chatter else 0.0)
        self.finger_speed_mps = self.chatter_mps if chatter else -self.creep_mps


def _close(gripper: ScriptedGripper, width_m: float, config: GraspConfig):
    task = close_until_stall(gripper, width_m, config)
    try:
        while True:
            next(task)
            gripper.step()
    except StopIteration as done:
        return done.value


def test_a_still_gap_with_a_chattering_speed_reading_is_a_stall():
    """Measured in packed `vgn` (MuesliBars, Patches): the gap stood within 0.1 mm at 40 N for
    8 s while the speed reading jumped to 3-6 mm/s a few times a second; method.md §7's speed rule
    alone never saw 0.5 s of slow readings and the close timed out."""
    cfg = GraspConfig()
    g = ScriptedGripper(object_m=0.0127, chatter_mps=0.006, chatter_every=100)
    gap = _close(g, 0.0162, cfg)
    assert gap == pytest.approx(0.0127, abs=0.0002)
    assert g.time_s < 1.5 * cfg.stall_time_s + 0.5  # contact after ~0.3 s, then one window


def test_without_the_gap_band_the_chattering_close_times_out():
    """The same readings with the still-gap rule off: the failure the rule removes."""
    cfg = replace(GraspConfig(), stall_gap_band_m=0.0)
    g = ScriptedGripper(object_m=0.0127, chatter_mps=0.006, chatter_every=100)
    with pytest.raises(StageFailure, match="close timed out"):
        _close(g, 0.0162, cfg)


def test_a_gap_that_keeps_moving_beyond_the_band_is_no_stall():
    """A pad sliding along the object (gap creeping 2 mm/s) with a chattering speed reading:
    the gap leaves the band within each window, so it is no stall (it creeps on to the
    command)."""
    cfg = GraspConfig()
    g = ScriptedGripper(object_m=0.030, chatter_mps=0.006, chatter_every=100, creep_mps=0.002)
    with pytest.raises(StageFailure, match="without stalling"):
        _close(g, 0.034, cfg)


def test_a_clean_stall_is_seen_by_the_speed_rule_at_the_same_time_as_before():
    """Without chatter: stalled ``stall_time_s`` after the contact, as method.md §7 says (the
    still-gap rule may fire a few steps sooner: the gap's last 0.5 mm of travel before the
    contact takes 6 ms at 80 mm/s)."""
    cfg = GraspConfig()
    g = ScriptedGripper(object_m=0.020, close_speed_mps=0.08)
    _close(g, 0.025, cfg)
    contact_s = (0.036 - 0.020) / 0.08
    assert g.time_s == pytest.approx(contact_s + cfg.stall_time_s, abs=3 * STEP_S)


def test_no_stall_is_called_before_the_window_has_passed_since_the_command():
    cfg = GraspConfig()
    watch = StallWatch(0.0, cfg)
    t = 0.0
    while t < cfg.stall_time_s:
        t += STEP_S
        assert not watch.update(t, 0.02, 0.0)


def test_after_the_stall_the_fingers_are_commanded_shut_at_the_closing_effort():
    """Holding is force-controlled: once stalled, the command is a shut gap at
    ``close_effort_N``, so the squeeze stays whatever the gap (an object creeping between the
    pads stays squeezed instead of the gap reaching the close command and the force fading)."""
    cfg = GraspConfig()
    g = ScriptedGripper(object_m=0.030)
    gap = _close(g, 0.034, cfg)
    assert gap == pytest.approx(0.030, abs=0.0002)
    assert g.command_m == 0.0 and g.effort_N == cfg.close_effort_N


def test_without_hold_by_force_the_close_command_stays():
    cfg = replace(GraspConfig(), hold_by_force=False)
    g = ScriptedGripper(object_m=0.030)
    _close(g, 0.034, cfg)
    assert g.command_m == pytest.approx(close_command_m(0.034, cfg))


class HeldReadings:
    def __init__(self, gap_m: float, force_N: float):
        self.finger_gap_m, self.gripper_force_N = gap_m, force_N


@pytest.mark.parametrize("gap_m, force_N, lost", [
    (0.030, 40.0, False),   # at the stall gap
    (0.020, 40.0, False),   # crept 10 mm at full squeeze: still pressing on the object
    (0.020, 2.0, True),     # narrower and no squeeze: nothing between the pads
    (0.029, 2.0, False),    # within held_gap_drop_m of the stall gap
    (0.002, 40.0, True),    # shut (pads on each other): the object left
])
def test_hold_lost(gap_m, force_N, lost):
    assert hold_lost(HeldReadings(gap_m, force_N), 0.030, GraspConfig()) is lost
