"""Clearing a table (ours, in the round rules of the VGN/GIGA benchmarks).

After the rough view and the active scan, :func:`clear_table` repeats: choose one target among
the perceived objects (:func:`~.targets.default_targets`; with ``order: accessibility`` the
one with the most free space for the fingers first, :mod:`.accessibility`; objects near an
earlier failed attempt last), attempt one pick (:func:`~.pick.pick_object`, which measures the target
from above again when its view is not NADIR), then **look again** — forget the tracks, since
a grasp may have moved the neighbours, and take a fresh rough view from the start pose.
It ends when no graspable object is proposed, after ``max_consecutive_failures`` failed
attempts in a row (VGN's rule: 2), or after ``max_attempts``.

Only the robot's own perception decides; ground truth (e.g. "the table is clear") is for the
benchmark that scores the round.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from typing import Callable, Optional

import numpy as np

from ..robot.description import hand_clearances
from .config import DeclutterConfig
from .events import StageEvent
from .grasping.accessibility import rank_by_accessibility
from .grasping.opening import full_margin_width_m
from .pick import PickContext, grasp_request, in_view, pick_object, return_to_start
from .scene.targets import default_targets
from .scene.tracks import nearest_track

log = logging.getLogger("grasp_pipeline.declutter")

#: Why a round ended.
END_NO_TARGET = "no graspable object proposed"
END_FAILURES = "consecutive failed attempts"
END_ATTEMPTS = "attempt limit"


@dataclass
class DeclutterOutcome:
    """The attempts of one round (:class:`~grasp_pipeline.results.PickResult`) and why it
    ended; ``skipped`` lists the tracks of the last look that were not targets (with ``why``:
    the grasp checks' notes, or the grasp source proposing no grasp)."""

    attempts: list = field(default_factory=list)
    end_reason: str = ""
    skipped: list = field(default_factory=list)


def order_targets(targets: list, failed_anchors: list, radius_m: float) -> list:
    """``targets`` (nearest the base first) with those within ``radius_m`` of a failed
    attempt's anchor moved to the end (their order kept)."""
    def failed_near(xy) -> bool:
        return any(float(np.hypot(xy[0] - a[0], xy[1] - a[1])) <= radius_m for a in failed_anchors)

    return [t for t in targets if not failed_near(t)] + [t for t in targets if failed_near(t)]


def look_again(ctx: PickContext) -> set:
    """Back to the start joints if needed, forget the tracks, a fresh rough view; returns the
    tids of that view."""
    return_to_start(ctx)
    ctx.loop.forget_tracks()
    ctx.action.picked_at.clear()
    ctx.rt.events.publish(StageEvent(float(ctx.rt.world.time_s), "look_again", perception=ctx.loop))
    ctx.rt.spin(ctx.settings.scan.rough_view_s)
    return {int(t.tid) for t in ctx.loop.tracks()}


#: What a grasp source offers for an object (:func:`grasp_offer`).
OFFER_NONE, OFFER_OTHER, OFFER_FITTED = 0, 1, 2


def grasp_offer(ctx: PickContext, xy) -> int:
    """What the grasp source offers for the object at ``xy``: ``OFFER_FITTED`` when it fits a
    grasp to the object's points (:mod:`.grasping.fit`), ``OFFER_OTHER`` when it proposes others
    only (the box grasps whose fingers' descent is free; any grasp of a source that fits none),
    ``OFFER_NONE`` when it proposes nothing (that object is not attempted in this look)."""
    track, _ = nearest_track(ctx.loop.tracks(), xy)
    if track is None:
        return OFFER_NONE
    request = grasp_request(ctx, xy, track)
    fitted = getattr(ctx.source, "fitted", None)
    if fitted is not None and fitted(request):
        return OFFER_FITTED
    return OFFER_OTHER if ctx.source.propose(request) else OFFER_NONE


def no_grasp_skip(ctx: PickContext, xy) -> dict:
    """The ``skipped`` entry of an object the grasp source proposes no grasp for, with the
    source's reason when it gives one (its ``last_refusal`` after :meth:`propose` returned none)."""
    track, _ = nearest_track(ctx.loop.tracks(), xy)
    why = f"grasp source {ctx.source.name!r} proposed no grasp"
    refusal = (getattr(ctx.source, "last_refusal", "") or "") if track is not None else "no track there"
    return {"tid": None if track is None else int(track.tid), "center": [float(xy[0]), float(xy[1])],
            "why": f"{why}: {refusal}" if refusal else why}


def best_score(ctx: PickContext, xy) -> float | None:
    """The score of the source's best grasp of the object at ``xy`` (None: no grasp)."""
    track, _ = nearest_track(ctx.loop.tracks(), xy)
    if track is None:
        return None
    grasps = ctx.source.propose(grasp_request(ctx, xy, track))
    return float(getattr(grasps[0], "score", 0.0)) if grasps else None


def _unseen(ctx: PickContext, xy) -> bool:
    """Whether the object at ``xy`` has no points in the latest frame (hidden from where the
    camera is: its pick measures it from above first, :func:`~.pick.pick_object`)."""
    track, _ = nearest_track(ctx.loop.tracks(), xy)
    return track is not None and not in_view(ctx.loop, track.tid)


def _by_score(ctx: PickContext, targets: list, skipped: Optional[list]) -> list:
    """Targets by their best grasp's score; those without a grasp because the latest frame
    does not show them come last (a closer look may find one), the others are left out."""
    scored, unseen = [], []
    for k, t in enumerate(targets):
        scored.append((best_score(ctx, t), k, t))
        if scored[-1][0] is None and _unseen(ctx, t):
            unseen.append(t)
        elif scored[-1][0] is None and skipped is not None:  # the source's reason is this object's now
            skipped.append(no_grasp_skip(ctx, t))
    ranked = sorted((x for x in scored if x[0] is not None), key=lambda x: (-x[0], x[1]))
    return [t for _, _, t in ranked] + unseen


def choose_order(ctx: PickContext, targets: list, failed_anchors: list, config: DeclutterConfig,
                 skipped: Optional[list] = None) -> list:
    """The round's target order: with ``order: score`` and a source that scores its grasps
    (not top-down only), the object with the best grasp first, then those the latest frame
    does not show (their pick looks from above first); else by accessibility (or
    nearest first), objects without a grasp fitted to their points after those with one
    (another object first: picking it may free them). Objects the source proposes no grasp
    for are left out (and added to ``skipped`` when given), failed places last."""
    if config.order == "score" and not getattr(ctx.source, "top_down_only", True):
        return order_targets(_by_score(ctx, targets, skipped), failed_anchors, config.failed_anchor_radius_m)
    if config.order in ("accessibility", "score"):
        s = ctx.settings
        targets = rank_by_accessibility(targets, ctx.loop.tracks(), hand_clearances(),
                                        s.grasp.open_margin_m, full_margin_width_m(s.grasp),
                                        config.free_space_enough_m)
    offers = []
    for t in targets:
        offers.append(grasp_offer(ctx, t))
        if offers[-1] == OFFER_NONE and skipped is not None:
            skipped.append(no_grasp_skip(ctx, t))
    targets = [t for t, f in zip(targets, offers) if f == OFFER_FITTED] + \
        [t for t, f in zip(targets, offers) if f == OFFER_OTHER]
    return order_targets(targets, failed_anchors, config.failed_anchor_radius_m)


def _ended(outcome: DeclutterOutcome, consecutive: int, cfg: DeclutterConfig) -> bool:
    if consecutive >= cfg.max_consecutive_failures:
        outcome.end_reason = f"{END_FAILURES} ({consecutive})"
    elif len(outcome.attempts) >= cfg.max_attempts:
        outcome.end_reason = f"{END_ATTEMPTS} ({cfg.max_attempts})"
    return bool(outcome.end_reason)


def _attempt(ctx: PickContext, targets: list, out: DeclutterOutcome):
    """(the first attempted pick's row, its target), trying ``targets`` in order: a target
    that the selection refuses after the closer look, or for which the grasp source then has no
    grasp, is declined — no attempt, it joins ``out.skipped`` — and the next one is tried;
    (None, None) when all are declined."""
    for xy in targets:
        log.info("attempt %d: %d target(s); picking at (%.3f, %.3f)", len(out.attempts) + 1,
                 len(targets), *xy)
        row = pick_object(ctx, xy, decline_without_grasp=True)
        if not row.declined:
            return row, xy
        track, _ = nearest_track(ctx.loop.tracks(), xy)
        out.skipped.append({"tid": None if track is None else int(track.tid),
                            "center": [float(xy[0]), float(xy[1])],
                            "why": f"after a closer look: {row.message}"})
    return None, None


def clear_table(ctx: PickContext, cell, rough_tids: set, config: DeclutterConfig,
                on_attempt: Optional[Callable] = None) -> DeclutterOutcome:
    """Pick objects one at a time until the rules end the round (see the module doc).

    ``cell``: the work cell (table top, tray); ``rough_tids``: the tracks of the first rough
    view; ``on_attempt(row)``: called after each attempt (e.g. a benchmark's bookkeeping)."""
    out, failed_anchors, consecutive = DeclutterOutcome(), [], 0
    margin = ctx.settings.grasp.target_fixture_margin_m
    while True:
        targets, out.skipped = default_targets(ctx.loop.tracks(), cell, margin, rough_tids,
                                               ctx.loop.judge)
        targets = choose_order(ctx, targets, failed_anchors, config, out.skipped)
        if not targets:
            out.end_reason = END_NO_TARGET
            break
        row, target = _attempt(ctx, targets, out)
        if row is None:
            out.end_reason = END_NO_TARGET
            break
        out.attempts.append(row)
        ok = bool(row.success and not row.failed_stage)  # the robot's own judgement
        consecutive = 0 if ok else consecutive + 1
        if not ok:
            failed_anchors.append(target)
        if on_attempt is not None:
            on_attempt(row)
        if _ended(out, consecutive, config):
            break
        rough_tids = look_again(ctx)
    log.info("round ended after %d attempt(s): %s", len(out.attempts), out.end_reason)
    return out
