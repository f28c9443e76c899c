"""Ground truth of each pick: how high the object really rose, how long it stayed up, and
whether it ended in the tray — a subscriber of the run's events (evaluation code only).

On ``StageEvent("pick_start", detail="x y")`` it picks the true object nearest the anchor and
follows its height on every :class:`~grasp_pipeline.orchestration.events.Tick`; when the hand
lifts (``StageEvent("LIFT")``) and one object touches both fingers, that object is followed
instead (in clutter the nearest centre can be a neighbour of what the hand closed on); on the
pick's :class:`~grasp_pipeline.orchestration.events.PickEvent` it fills ``object``,
``lift_m``, ``held_s`` and ``placed`` of the :class:`~grasp_pipeline.results.PickResult`.
"""

from __future__ import annotations

import math
from typing import Optional

import numpy as np

from ..orchestration.events import EventBus, PickEvent, StageEvent, Tick
from ..sim.ground_truth import object_body_id, object_truths
from ..sim.object_geoms import OBJECT_PREFIX, geom_object

#: The report's "lifted" threshold [m] (an object counts as held while ≥ this above its start).
MIN_LIFT_EVAL_M = 0.05
#: An object counts as in the tray up to this far below / above the tray floor [m].
TRAY_BELOW_M = 0.01
TRAY_ABOVE_M = 0.15


def nearest_truth_name(world, xy) -> Optional[str]:
    truths = object_truths(world)
    if not truths:
        return None
    d = [np.linalg.norm(t.position_m[:2] - np.asarray(xy)[:2]) for t in truths]
    return truths[int(np.argmin(d))].name


def tray_holds(cell, p) -> bool:
    """True when the point ``p`` [m] lies over the tray floor's footprint of the work cell
    ``cell``, near its height."""
    half = 0.5 * float(cell.tray_floor.extents[0])
    centre = cell.tray_center_m
    return bool(abs(p[0] - centre[0]) <= half and abs(p[1] - centre[1]) <= half
                and centre[2] - TRAY_BELOW_M <= p[2] <= centre[2] + TRAY_ABOVE_M)


def in_tray(world, name: str) -> bool:
    """True when object ``name`` lies over the tray floor's footprint, near its height."""
    for t in object_truths(world):
        if t.name == name:
            return tray_holds(world.work_cell, t.position_m)
    return False


def lift_figures(samples: list, z0: float, released_at: Optional[float], min_lift_m: float) -> dict:
    """``lift_m``: highest rise before release; ``held_s``: time at ≥ ``min_lift_m``."""
    arr = np.asarray(samples, dtype=float).reshape(-1, 2)
    if released_at is not None:
        arr = arr[arr[:, 0] <= released_at]
    if len(arr) < 2:
        return {"lift_m": 0.0, "held_s": 0.0}
    rise = arr[:, 1] - z0
    dt = np.diff(arr[:, 0], append=arr[-1, 0])
    return {"lift_m": float(rise.max()), "held_s": float(dt[rise >= min_lift_m].sum())}


def between_fingers(world) -> Optional[str]:
    """The object both fingers touch now (None: none, or more than one)."""
    sides: dict = {"leftfinger": set(), "rightfinger": set()}
    for robot_geom, other in world.robot_contacts():
        if not other.startswith(OBJECT_PREFIX):
            continue
        for side, names in sides.items():
            if side in robot_geom:
                names.add(geom_object(other)[len(OBJECT_PREFIX):])
    both = sides["leftfinger"] & sides["rightfinger"]
    return next(iter(both)) if len(both) == 1 else None


class PickEvaluator:
    """Subscribe with :meth:`attach`; fills each pick's ground-truth fields."""

    def __init__(self, world) -> None:
        self.world = world
        self.name: Optional[str] = None
        self.z0 = math.nan
        self.samples: list = []
        self._body: Optional[int] = None  # MuJoCo body id of the followed object
        self._xpos = None  # the bodies' positions (MuJoCo's view, read at every tick while following)
        self._start_z: dict = {}  # every object's height when the pick started

    def attach(self, events: EventBus) -> "PickEvaluator":
        events.subscribe(StageEvent, self.on_stage)
        events.subscribe(Tick, self.on_tick)
        events.subscribe(PickEvent, self.on_pick)
        return self

    def on_stage(self, ev: StageEvent) -> None:
        if ev.name == "pick_start":
            x, y = (float(v) for v in ev.detail.split())
            self._start_z = {t.name: float(t.position_m[2]) for t in object_truths(self.world)}
            self._follow(nearest_truth_name(self.world, (x, y)), math.nan)
        elif ev.name == "LIFT" and self.name is not None:
            held = between_fingers(self.world)
            if held is not None and held != self.name and held in self._start_z:
                self._follow(held, self._start_z[held])

    def _follow(self, name: Optional[str], z0: float) -> None:
        self.name, self.z0, self.samples = name, z0, []
        self._body = None if name is None else object_body_id(self.world, name)
        self._xpos = self.world.data.xpos

    def on_tick(self, ev: Tick) -> None:
        """Sample the followed object's height (every tick: read straight from the body)."""
        if self.name is None or self._body is None:
            return
        z = float(self._xpos[self._body, 2])
        self.z0 = z if math.isnan(self.z0) else self.z0
        self.samples.append((float(ev.time_s), z))

    def on_pick(self, ev: PickEvent) -> None:
        row, name = ev.result, self.name
        self.name = None
        if name is None:
            return
        row.object = name
        if self.samples and row.stages:
            fig = lift_figures(self.samples, self.z0, ev.release_time_s, MIN_LIFT_EVAL_M)
            row.lift_m, row.held_s = fig["lift_m"], fig["held_s"]
        row.placed = bool(row.placed and in_tray(self.world, name))
