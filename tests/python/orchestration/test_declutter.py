"""Clearing a table: target order and the round rules (VGN: 2 consecutive failures end a
round), with fake picks — the real picks run in the clutter benchmark's tests."""

from types import SimpleNamespace

import pytest

from grasp_pipeline import _core
from grasp_pipeline.orchestration import declutter
from grasp_pipeline.orchestration.config import DeclutterConfig
from grasp_pipeline.orchestration.scene.selection import spec_judge
from grasp_pipeline.results import PickResult


def _track(tid, x, y):
    est = SimpleNamespace(center=[x, y, 0.22], grasp_ok=True, notes=[])
    return SimpleNamespace(tid=tid, smoothed=est, quality=_core.ViewQuality.NADIR)


class _Cloud:
    """The latest frame's points: one per track except the ``unseen`` tids."""

    def __init__(self, unseen=()):
        self.unseen = set(unseen)

    def of(self, tid):
        return [] if tid in self.unseen else [(0.0, 0.0, 0.0)]


class _Cell:
    def pick_target_note(self, xy, margin):
        return None


def test_targets_near_a_failed_anchor_go_last():
    targets = [(0.40, 0.0), (0.45, 0.0), (0.50, 0.1)]
    out = declutter.order_targets(targets, failed_anchors=[(0.41, 0.0)], radius_m=0.03)
    assert out == [(0.45, 0.0), (0.50, 0.1), (0.40, 0.0)]


@pytest.fixture
def fake(monkeypatch):
    """A context whose table holds ``state['objects']``; a pick succeeds per ``state['plan']``."""
    state = {"objects": [(0.40, 0.0), (0.50, 0.0), (0.60, 0.0)], "plan": [], "looks": 0}
    loop = SimpleNamespace(tracks=lambda: [_track(i, *xy) for i, xy in enumerate(state["objects"])],
                           judge=spec_judge, scene_cloud=lambda: _Cloud(state.get("unseen", ())))
    ctx = SimpleNamespace(loop=loop, settings=SimpleNamespace(grasp=SimpleNamespace(target_fixture_margin_m=0.03)),
                          source=SimpleNamespace(name="fake", propose=lambda request: ["a grasp"]))
    monkeypatch.setattr(declutter, "grasp_request", lambda _ctx, xy, track: (xy, track.tid))

    def pick(_ctx, xy, decline_without_grasp=False):
        ok = state["plan"].pop(0)
        if ok is None:  # no grasp after the closer look
            return PickResult(anchor=list(xy), failed_stage="GRASP", declined=decline_without_grasp)
        if ok:
            state["objects"].remove(tuple(xy))
        return PickResult(anchor=list(xy), success=ok, failed_stage=None if ok else "CLOSE")

    def look(_ctx):
        state["looks"] += 1
        return {t.tid for t in loop.tracks()}

    monkeypatch.setattr(declutter, "pick_object", pick)
    monkeypatch.setattr(declutter, "look_again", look)
    return ctx, state


def test_round_clears_the_table_and_ends_when_nothing_is_proposed(fake):
    ctx, state = fake
    state["plan"] = [True, False, True, True]
    out = declutter.clear_table(ctx, _Cell(), {0, 1, 2}, DeclutterConfig(order="nearest"))
    assert [a.success for a in out.attempts] == [True, False, True, True]
    assert out.end_reason == declutter.END_NO_TARGET and state["objects"] == []
    # after the failure at (0.5, 0) the next attempt went to the other object first
    assert [a.anchor for a in out.attempts][1:3] == [[0.5, 0.0], [0.6, 0.0]]
    assert state["looks"] == len(out.attempts)


def test_two_failures_in_a_row_end_the_round(fake):
    ctx, state = fake
    state["plan"] = [False, False, True]
    out = declutter.clear_table(ctx, _Cell(), {0, 1, 2}, DeclutterConfig(max_consecutive_failures=2, order="nearest"))
    assert len(out.attempts) == 2 and out.end_reason.startswith(declutter.END_FAILURES)


def test_attempt_limit(fake):
    ctx, state = fake
    state["plan"] = [False, True, False, True]
    out = declutter.clear_table(ctx, _Cell(), {0, 1, 2}, DeclutterConfig(max_attempts=3, order="nearest"))
    assert len(out.attempts) == 3 and out.end_reason.startswith(declutter.END_ATTEMPTS)


def test_objects_without_a_fitted_grasp_go_after_the_others(monkeypatch):
    offers = {(0.40, 0.0): declutter.OFFER_OTHER, (0.45, 0.0): declutter.OFFER_FITTED,
              (0.50, 0.1): declutter.OFFER_FITTED, (0.55, 0.0): declutter.OFFER_NONE}
    monkeypatch.setattr(declutter, "grasp_offer", lambda ctx, xy: offers[xy])
    cfg = DeclutterConfig(order="nearest")
    out = declutter.choose_order(None, list(offers), [(0.50, 0.1)], cfg)
    # no fit: after; nothing proposed: left out; failed place: last
    assert out == [(0.45, 0.0), (0.40, 0.0), (0.50, 0.1)]


@pytest.mark.parametrize("fitted, proposed, expected", [
    (["g"], ["g", "box"], declutter.OFFER_FITTED),
    ([], ["box"], declutter.OFFER_OTHER),
    ([], [], declutter.OFFER_NONE),
    (None, ["learned"], declutter.OFFER_OTHER),  # a source that fits nothing: its proposals count
    (None, [], declutter.OFFER_NONE),
])
def test_grasp_offer_says_what_the_source_offers(fake, monkeypatch, fitted, proposed, expected):
    ctx, _ = fake
    ctx.source = SimpleNamespace(name="s", propose=lambda request: proposed)
    if fitted is not None:
        ctx.source.fitted = lambda request: fitted
    assert declutter.grasp_offer(ctx, (0.50, 0.0)) == expected


def test_a_round_ends_when_the_source_proposes_nothing(fake):
    ctx, state = fake
    ctx.source = SimpleNamespace(name="s", propose=lambda request: [])
    out = declutter.clear_table(ctx, _Cell(), {0, 1, 2}, DeclutterConfig(order="nearest"))
    assert out.attempts == [] and out.end_reason == declutter.END_NO_TARGET
    assert len(state["objects"]) == 3


def test_a_target_without_a_grasp_after_its_closer_look_is_no_attempt(fake):
    """The closer look just before a pick can leave the source without a grasp: the robot
    declines that object (it joins the skipped ones with the reason) and tries the next one
    in the same look; no attempt is counted, no failure either."""
    ctx, state = fake
    state["plan"] = [None, True, None, True, None]
    out = declutter.clear_table(ctx, _Cell(), {0, 1, 2}, DeclutterConfig(order="nearest"))
    assert [a.anchor for a in out.attempts] == [[0.5, 0.0], [0.6, 0.0]]
    assert all(a.success for a in out.attempts)
    assert out.end_reason == declutter.END_NO_TARGET and state["objects"] == [(0.40, 0.0)]
    assert any(s["why"].startswith("after a closer look") for s in out.skipped)


def test_objects_the_source_proposes_nothing_for_are_skipped_with_the_reason(fake, monkeypatch):
    ctx, _ = fake
    offers = {(0.40, 0.0): declutter.OFFER_FITTED, (0.60, 0.0): declutter.OFFER_NONE}
    monkeypatch.setattr(declutter, "grasp_offer", lambda _ctx, xy: offers[xy])
    ctx.source.last_refusal = "no closing line passes the point checks (a finger blocked)"
    skipped = [{"tid": 9, "center": [0.7, 0.0], "why": "near the tray"}]
    out = declutter.choose_order(ctx, list(offers), [], DeclutterConfig(order="nearest"), skipped)
    assert out == [(0.40, 0.0)]
    assert skipped[1] == {"tid": 2, "center": [0.60, 0.0], "why": "grasp source 'fake' proposed no grasp: "
                                                                   "no closing line passes the point checks (a finger blocked)"}
    del ctx.source.last_refusal  # a source that gives no reason
    skipped = []
    declutter.choose_order(ctx, list(offers), [], DeclutterConfig(order="nearest"), skipped)
    assert [s["why"] for s in skipped] == ["grasp source 'fake' proposed no grasp"]


def test_a_round_ended_for_want_of_grasps_lists_every_object_as_skipped(fake):
    ctx, state = fake
    ctx.source = SimpleNamespace(name="s", propose=lambda request: [])
    out = declutter.clear_table(ctx, _Cell(), {0, 1, 2}, DeclutterConfig(order="nearest"))
    assert out.end_reason == declutter.END_NO_TARGET
    assert sorted(s["tid"] for s in out.skipped) == [0, 1, 2]
    assert all(s["why"] == "grasp source 's' proposed no grasp" for s in out.skipped)


def test_ranked_by_score_each_skipped_object_keeps_its_own_refusal(fake):
    """The source's ``last_refusal`` is that of its latest proposal: each object without a grasp
    is skipped with the reason given for it, not with a later object's (an empty one when the
    later object had grasps)."""
    ctx, _ = fake
    reasons = {0.40: "too wide to close on", 0.50: "", 0.60: "the hand meets a neighbour"}

    class Source:
        name, top_down_only, last_refusal = "scored", False, ""

        def propose(self, request):
            x = round(float(request[0][0]), 2)  # the fake request: (xy, tid)
            self.last_refusal = reasons[x]
            return [] if reasons[x] else [SimpleNamespace(score=0.9)]

    ctx.source = Source()
    skipped: list = []
    targets = [(0.40, 0.0), (0.50, 0.0), (0.60, 0.0)]
    out = declutter.choose_order(ctx, targets, [], DeclutterConfig(order="score"), skipped)
    assert out == [(0.50, 0.0)]
    assert [s["why"] for s in skipped] == ["grasp source 'scored' proposed no grasp: too wide to close on",
                                           "grasp source 'scored' proposed no grasp: the hand meets a neighbour"]


def test_ranked_by_score_an_object_the_latest_frame_does_not_show_comes_last(fake):
    """No grasp because the latest frame holds none of its points (hidden behind a neighbour
    from where the camera is): not skipped but tried last — its pick measures it from above
    first; an object seen and refused stays skipped."""
    ctx, state = fake
    state["unseen"] = {0}

    class Source:
        name, top_down_only, last_refusal = "scored", False, ""

        def propose(self, request):
            x = round(float(request[0][0]), 2)
            self.last_refusal = "no points in the latest frame" if x == 0.40 else (
                "too wide to close on" if x == 0.60 else "")
            return [] if self.last_refusal else [SimpleNamespace(score=0.9)]

    ctx.source = Source()
    skipped: list = []
    targets = [(0.40, 0.0), (0.50, 0.0), (0.60, 0.0)]
    out = declutter.choose_order(ctx, targets, [], DeclutterConfig(order="score"), skipped)
    assert out == [(0.50, 0.0), (0.40, 0.0)]
    assert [s["tid"] for s in skipped] == [2]
