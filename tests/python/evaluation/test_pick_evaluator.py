"""The pick evaluator follows the object the hand closed on: the true object nearest the anchor
at the start, the one both fingers touch once the hand lifts (a neighbour's centre can be nearer
the anchor in clutter). A small stand-in world: contacts and body heights, no simulator."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from grasp_pipeline.evaluation import pick_evaluator as pe
from grasp_pipeline.orchestration.events import PickEvent, StageEvent, Tick
from grasp_pipeline.results import PickResult

NAMES = ["a", "b"]


class World:
    def __init__(self) -> None:
        self.data = SimpleNamespace(xpos=np.array([[0.50, 0.00, 0.02], [0.53, 0.00, 0.03]]))
        self.contacts: list = []

    def robot_contacts(self):
        return list(self.contacts)


def _truths(world):
    return [SimpleNamespace(name=n, position_m=world.data.xpos[k]) for k, n in enumerate(NAMES)]


def _run(monkeypatch, contacts) -> PickResult:
    monkeypatch.setattr(pe, "object_truths", _truths)
    monkeypatch.setattr(pe, "object_body_id", lambda world, name: NAMES.index(name))
    world = World()
    ev = pe.PickEvaluator(world)
    ev.on_stage(StageEvent(0.0, "pick_start", "0.50 0.0"))  # nearest centre: a
    ev.on_tick(Tick(0.1))
    world.contacts = contacts
    ev.on_stage(StageEvent(1.0, "LIFT"))
    for k in range(10):  # b rises by 0.2 m, a stays
        world.data.xpos[1, 2] = 0.03 + 0.02 * (k + 1)
        ev.on_tick(Tick(1.0 + 0.1 * k))
    row = PickResult(anchor=[0.5, 0.0], stages=[("CLOSE", 0.5), ("LIFT", 1.0)])
    ev.on_pick(PickEvent(2.0, row))
    return row


def test_the_object_between_the_fingers_is_followed_once_the_hand_lifts(monkeypatch):
    row = _run(monkeypatch, [("leftfinger_pad", "obj_b_p0"), ("rightfinger_pad", "obj_b"),
                             ("leftfinger_col0", "obj_a"), ("hand_col", "table")])
    assert row.object == "b" and abs(row.lift_m - 0.2) < 1e-9 and row.held_s > 0


def test_without_one_object_between_the_fingers_the_nearest_stays_followed(monkeypatch):
    row = _run(monkeypatch, [("leftfinger_pad", "obj_b"), ("rightfinger_pad", "obj_a")])
    assert row.object == "a" and row.lift_m == 0.0
