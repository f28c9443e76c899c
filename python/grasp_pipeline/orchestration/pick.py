"""One pick: (re-probe) → select → verify the published grasp → grasp source → grasp action.

:func:`pick_object` is the sequence the run performs for every target position:

1. let ``settle_view_s`` of fresh frames arrive (looking: the camera renders only while a
   pick looks — here, during a re-probe's dwell and during the selection's verification;
   the grasp action's motions render nothing);
2. re-probe (ours): a NADIR track retires ``nadir_hold_s`` after it was last seen (judged
   when a frame arrives, after that frame's observations: with frames on demand, at the
   settle view, for an object not in view there; with continuous frames also while the
   camera looks at the tray during a place) and an oblique view misjudges what a grasp
   needs, so an object whose track is no longer NADIR — or is gone, or has no points in the
   latest frame (hidden behind a neighbour from where the camera is) — is measured from above
   again;
3. select by position (method.md §5) and verify that best grasps actually arrive (a dead upstream
   must not look like success);
4. (ours) when a side view is configured (``PickContext.side_view``) and the target's sides
   are mostly unknown in the scene volume, look at them first (:mod:`.side_view`);
5. ask the :class:`~.grasping.source.GraspSource` for candidates and run the grasp action; after
   an attempt, the scene volume forgets the target's surroundings (objects may have moved).

It publishes ``StageEvent("pick_start", "x y")`` when the grasp starts and a
:class:`~.events.PickEvent` at the end (evaluation subscribers may add ground truth to the
result before it is reported).
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from .. import _core
from ..results import PickResult
from .events import PickEvent, StageEvent
from .execution.place import recover
from .execution.stages import Stage
from .grasping.opening import max_grasp_width_m
from .grasping.reach import ArmReach
from .grasping.source import GraspRequest, GraspSource
from .grasping.top_down import GeometricGraspSource
from .scanning.side_view import look_at_sides
from .scene.scene_model import snapshot
from .scene.selection import check_selection

log = logging.getLogger("grasp_pipeline.pick")


@dataclass
class PickContext:
    """The parts a pick uses (built by the composition root)."""

    rt: object            # Runtime
    loop: object          # PerceptionLoop
    action: object        # GraspAction
    scanner: Optional[object]  # ActiveScan (None: no re-probe)
    settings: object      # Settings: scan, grasp, obb, motion
    source: GraspSource = field(default_factory=GeometricGraspSource)
    place: bool = True
    side_view: Optional[object] = None  # SideView (None: no look at the target's sides)


def in_view(loop, tid: int) -> bool:
    """Whether the latest frame holds points of track ``tid`` (False: hidden or out of view
    from where the camera is now — a track kept from an earlier view)."""
    cloud = loop.scene_cloud()
    return cloud is not None and len(cloud.of(int(tid))) > 0


def _wait_in_view(ctx: PickContext, tid: int) -> bool:
    """Look until a frame shows track ``tid``, up to ``scan.target_view_timeout_s``; whether one
    did. The grasp source reads the object's points from the latest frame, and where the
    tracker holds two tracks of one object (an L or T shape seen as two parts, say) the other
    track takes its points in some frames."""
    loop = ctx.loop
    if in_view(loop, tid):
        return True
    return ctx.rt.spin_until(lambda: in_view(loop, tid), ctx.settings.scan.target_view_timeout_s,
                             look=True)


def _reprobe_centre(ctx: PickContext, xy) -> Optional[np.ndarray]:
    """Where to look from above before picking at ``xy`` (None: the track is NADIR and in
    view)."""
    loop = ctx.loop
    chk = check_selection(float(xy[0]), float(xy[1]), loop.tracks(), loop.gate_m, loop.plane,
                          loop.selector.fallback_limit_m, loop.selector.judge)
    track = None if chk.kind in ("far", "nothing") else chk.track
    if (track is not None and track.quality == _core.ViewQuality.NADIR
            and in_view(loop, track.tid)):
        return None
    if track is not None:
        return np.asarray(track.smoothed.center, float)
    if loop.plane is None:
        return None
    n, c = np.asarray(loop.plane.n, float), float(loop.plane.c)  # retired: look where it was
    return np.array([xy[0], xy[1], -(c + n[0] * xy[0] + n[1] * xy[1]) / n[2]])


def reprobe_if_needed(ctx: PickContext, xy, row: PickResult) -> None:
    centre = _reprobe_centre(ctx, xy)
    if centre is None or ctx.scanner is None:
        return
    res = ctx.scanner.trigger(centres=[centre])
    if not res.accepted:
        return
    try:
        out = ctx.rt.run(ctx.scanner.task, ctx.settings.scan.scan_timeout_s)
    except TimeoutError as exc:
        ctx.rt.world.hold()
        log.warning("re-probe did not finish: %s", exc)
        row.reprobed = False
        return
    row.reprobed = bool(out.probes and out.probes[0].nadir)
    ctx.rt.spin(ctx.settings.scan.settle_view_s)


def side_view_if_needed(ctx: PickContext, xy, row: PickResult) -> None:
    """Look at the sides of the object at ``xy`` when they are mostly unknown (:mod:`.side_view`)."""
    if ctx.side_view is None:
        return
    track = ctx.loop.nearest_track(np.asarray(xy, float))
    if track is None:
        return
    row.side_view = look_at_sides(ctx.side_view, track, ctx.settings.scan.scan_timeout_s)


def _look_again_at_sides(ctx: PickContext, xy, row: PickResult) -> bool:
    """No grasp from what was seen: when no side view was taken for this pick, take one now
    if the target's sides are at all unknown (True: a view was taken — ask again)."""
    if ctx.side_view is None or (row.side_view is not None and row.side_view.view is not None):
        return False
    track = ctx.loop.nearest_track(np.asarray(xy, float))
    if track is None:
        return False
    result = look_at_sides(ctx.side_view, track, ctx.settings.scan.scan_timeout_s, force=True)
    if result.view is None:
        return False
    row.side_view = result
    return True


def _forget_attempted(ctx: PickContext, estimate) -> None:
    """The scene volume forgets the surroundings of the attempted target (``estimate``: its
    box before the attempt; it may have moved)."""
    volume = getattr(ctx.loop, "volume", None)
    if volume is not None and estimate is not None:
        volume.forget_after_attempt(estimate.center, estimate.R_box, estimate.extents)


def _select_and_verify(ctx: PickContext, xy, row: PickResult, decline: bool = False):
    """The selection result, or None with ``row`` marked as a SELECT failure (``decline``:
    declined instead — the selection refused the object after the closer look, before the arm
    moved to grasp it, so that is no attempt)."""
    loop, scan_cfg = ctx.loop, ctx.settings.scan
    sel = loop.select(*xy)
    if not sel.ok:
        row.failed_stage, row.message, row.declined = Stage.SELECT, sel.message, decline
        return None
    if not ctx.rt.spin_until(lambda: loop.selector.published >= scan_cfg.select_verify_frames,
                             scan_cfg.stale_timeout_s, look=True):
        row.failed_stage, row.declined = Stage.SELECT, decline
        row.message = f"selected, but no best grasp arrived within {scan_cfg.stale_timeout_s} s"
        loop.selector.clear()
        return None
    row.selected = sel.message
    return sel


def grasp_request(ctx: PickContext, xy, target, check_collisions: bool = False) -> GraspRequest:
    """What the grasp source gets for the object ``target`` (a track) at ``xy``: the latest
    published grasp, the perceived scene, the scene's labelled points and the arm's reach
    (``check_collisions``: the planner's scene is set for this target first, and a reachable
    grasp also needs collision-free joints at the grasp and the pre-grasp)."""
    loop, s = ctx.loop, ctx.settings
    motion = ctx.action.motion
    scene = snapshot(loop, exclude_tids=ctx.action.lingering_tids())
    if check_collisions and target is not None:
        motion.set_scene(scene.without_fragments(int(target.tid), s.grasp.fragment_margin_m),
                         int(target.tid))
    # the arm's reach is checked only for the pick itself (ranking the round's targets
    # needs the grasps' scores, not their reach)
    reach = ArmReach(motion.planner, motion.q_cmd, ctx.rt.world.tcp_pose(), True) if check_collisions else None
    volume = getattr(loop, "volume", None)
    return GraspRequest(anchor_xy=(float(xy[0]), float(xy[1])), target=target,
                        published=loop.selector.best_grasp, scene=scene,
                        max_width_m=max_grasp_width_m(s.grasp_fit),
                        cloud=loop.scene_cloud(), min_width_m=s.obb.min_graspable_width,
                        reach=reach, volume=volume, unknown=None if volume is None else volume.not_free)


def _candidates(ctx: PickContext, xy, sel) -> list:
    _wait_in_view(ctx, int(sel.tid))
    target = next((t for t in ctx.loop.tracks() if t.tid == sel.tid), None)
    return list(ctx.source.propose(grasp_request(ctx, xy, target, check_collisions=True)))


def _run_action(ctx: PickContext, xy, sel, row: PickResult, decline: bool = False):
    """Grasp (and place) with the source's candidates; the action's outcome or None.
    ``decline``: when the source proposes nothing, the pick is declined (not attempted)."""
    rt, loop, action = ctx.rt, ctx.loop, ctx.action
    try:
        grasps = _candidates(ctx, xy, sel)
        if not grasps and _look_again_at_sides(ctx, xy, row):
            grasps = _candidates(ctx, xy, sel)
        if not grasps:
            row.failed_stage, row.declined = Stage.GRASP, decline
            why = getattr(ctx.source, "last_refusal", "")
            row.message = f"grasp source {ctx.source.name!r} proposed no grasp" + (f": {why}" if why else "")
            return None
        ok, msg = action.start(grasps[0], place=ctx.place, alternatives=grasps[1:])
        if not ok:
            row.failed_stage, row.message = Stage.GRASP, msg
            return None
        # The action holds its goal now: stop re-resolving the anchor (once the object is
        # lifted there is nothing left to publish there, and that is no news).
        loop.selector.clear()
        attempted = next((t.smoothed for t in loop.tracks() if t.tid == sel.tid), None)
        rt.events.publish(StageEvent(float(rt.world.time_s), "pick_start", f"{xy[0]} {xy[1]}"))
        out = None
        try:
            out = rt.run(action.task, ctx.settings.grasp.pick_timeout_s)
            return out
        except TimeoutError as exc:  # the task was closed: the arm holds where it is
            rt.world.hold()
            row.failed_stage = action.stage if action.stage is not None else Stage.GRASP
            row.message = f"{exc}; the arm holds"
            return None
        finally:
            if out is None or any(stage != Stage.PRE_GRASP for stage, _ in out.stages):
                _forget_attempted(ctx, attempted)  # the hand went down to the object
    finally:
        loop.selector.clear()


def return_to_start(ctx: PickContext) -> None:
    """When an earlier failure left the arm away from its start joints (e.g. stopped by a
    contact and unable to retreat), recover first: open, move away from the contact, go home —
    so the next pick does not begin from an invalid start state."""
    action, rt = ctx.action, ctx.rt
    if action.home_q is None or action.task is not None and not action.task.done:
        return
    err = float(np.max(np.abs(np.asarray(rt.world.q) - action.home_q)))
    if err <= ctx.settings.motion.settle_position_tol_rad:
        return
    log.warning("the arm is %.3f rad from its start joints before the next pick: recovering first", err)
    try:
        rt.run(rt.start("recover", recover(action)), ctx.settings.grasp.pick_timeout_s)
    except TimeoutError as exc:
        rt.world.hold()
        log.error("recovery did not finish: %s", exc)


def pick_object(ctx: PickContext, xy, decline_without_grasp: bool = False) -> PickResult:
    """Pick (and place) the object at ``xy`` [m, world]; see the module doc.

    ``decline_without_grasp``: when, after the closer look, the selection refuses the object or
    the grasp source proposes no grasp, the pick is declined — ``row.declined``, no :class:`PickEvent`: the arm made no
    attempt (clearing a table then tries another object)."""
    wall0 = time.perf_counter()
    return_to_start(ctx)
    ctx.rt.spin(ctx.settings.scan.settle_view_s)
    row = PickResult(anchor=[float(xy[0]), float(xy[1])], grasp_source=ctx.source.name)
    if ctx.scanner is not None:
        reprobe_if_needed(ctx, xy, row)
    side_view_if_needed(ctx, xy, row)
    out = None
    sel = _select_and_verify(ctx, xy, row, decline_without_grasp)
    if sel is not None:
        out = _run_action(ctx, xy, sel, row, decline_without_grasp)
    if row.declined:
        row.wall_s = time.perf_counter() - wall0
        log.info("pick at (%.3f, %.3f) declined: %s", xy[0], xy[1], row.message)
        return row
    if out is not None:
        row.success, row.failed_stage = out.success, out.failed_stage
        row.message = out.message or "picked"
        row.stages, row.stall_gap_m, row.width_m = out.stages, out.stall_gap_m, out.width_m
        row.grasp = out.grasp
        row.placed = bool(out.placed)
    row.wall_s = time.perf_counter() - wall0
    ctx.rt.events.publish(PickEvent(float(ctx.rt.world.time_s), row,
                                    None if out is None else out.release_time_s))
    return row
