"""``grasp-pipeline run``: rough view → active scan → pick (and place) the selected objects.

One function, :func:`run_pipeline`, wires the parts together — the simulated world and its
camera, the perception loop, the motion client, the scan, selection and the grasp action —
and writes the report JSON, PNG snapshots (after the rough view and after the scan) and an
MP4. Ground truth enters only through :mod:`.scoring`, for the report's scores.
"""

from __future__ import annotations

import json
import logging
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Optional, Sequence

import numpy as np

from .. import _core
from ..exceptions import InputError
from ..motion.motion_planner import MotionPlanner
from ..perception import PerceptionSession
from ..report.snapshot import render_snapshot
from ..settings import Settings, load_settings
from ..sim.robot_model import flange_T_camera
from ..sim.scenes import random_scene, reference_scene
from ..sim.world import SimWorld
from .grasp_action import GraspAction
from .motion_client import MotionClient
from .perception_loop import PerceptionLoop
from .recorder import RunRecorder
from .runtime import Runtime
from .scan import ActiveScan
from .selection import check_selection, perpendicular_grasp
from .work_cell import WorkCell
from . import scoring

log = logging.getLogger("grasp_pipeline.run")

SECTIONS = ("scene_filter", "obb", "camera", "sim", "motion", "scan", "grasp")
ROUGH_VIEW_S = 0.5           # frames at the start pose before the scan (plane hardens after 5)
SETTLE_VIEW_S = 0.3          # fresh frames at the start pose before each selection
SCAN_TIMEOUT_S = 120.0       # simulated
PICK_TIMEOUT_S = 90.0        # simulated
TRAY_SITE = "tray_centre"
TRAY_FLOOR_GEOM = "tray_floor"
MIN_LIFT_EVAL_M = 0.05       # the report's "lifted" threshold (issue: ≥ 5 cm)


def _snapshot(loop: PerceptionLoop, path: Path, title: str) -> str:
    res = loop.latest.result
    obj, labels = res.object_points()
    boxes, grasps = [], []
    plane = loop.plane
    for tr in loop.tracks():
        e = tr.smoothed
        boxes.append((np.asarray(e.center), np.asarray(e.R_box), np.asarray(e.extents)))
        top = np.asarray(e.center) + 0.5 * e.height_m * np.asarray(plane.n)
        grasps.append((top, -np.asarray(plane.n)))
    return render_snapshot(path, obj, labels, res.environment_points(), boxes, grasps,
                           plane=plane, title=title)


def _tracks_report(loop: PerceptionLoop) -> list[dict]:
    out = []
    for tr in loop.tracks():
        e = tr.smoothed
        out.append({"tid": int(tr.tid), "quality": tr.quality.name, "pca_tilt_deg": float(e.pca_tilt_deg),
                    "center": [float(x) for x in e.center],
                    "extents": [float(x) for x in e.extents],
                    "theta_deg": float(np.degrees(e.theta_rad)), "grasp_ok": bool(e.grasp_ok),
                    "notes": list(e.notes)})
    return out


def _default_targets(loop: PerceptionLoop, cell: WorkCell, fixture_margin_m: float,
                     rough_tids: set[int]) -> tuple[list[tuple[float, float]], list[dict]]:
    """Every object on the table that passes its grasp checks, nearest to the robot base
    first; and the tracks left out, each with why (too wide — e.g. a piece of the tray's
    rim —, over the tray, off the table, or first seen during the scan and never measured
    from above: a glimpse of the far table from a probe pose, not an object the scan probed).

    ``rough_tids``: the tracks of the rough view (the objects the scan set out to measure)."""
    targets, skipped = [], []
    for t in loop.tracks():
        c = np.asarray(t.smoothed.center[:2], float)
        note = cell.pick_target_note(c, fixture_margin_m)
        if note is None and t.tid not in rough_tids and t.quality != _core.ViewQuality.NADIR:
            note = (f"#{t.tid} was first seen during the scan ({t.quality.name.lower()} view) and "
                    f"never measured from above")
        if note is None and not t.smoothed.grasp_ok:
            note = "; ".join(t.smoothed.notes) or "grasp checks failed"
        if note is None:
            targets.append(c)
        else:
            skipped.append({"tid": int(t.tid), "center": [float(c[0]), float(c[1])], "why": note})
    targets.sort(key=lambda c: float(np.hypot(*c)))
    return [(float(c[0]), float(c[1])) for c in targets], skipped


@dataclass
class System:
    """Every running part of one headless session."""

    world: SimWorld
    loop: PerceptionLoop
    rt: Runtime
    motion: MotionClient
    scanner: ActiveScan
    action: GraspAction
    tray: np.ndarray
    start_q: np.ndarray

    def close(self) -> None:
        self.world.close()


def build_system(spec, settings: Settings) -> System:
    """World + camera → perception loop; motion client; scan; grasp action (not started)."""
    world = SimWorld(spec, settings.sim, settings.camera)
    try:
        session = PerceptionSession(settings.scene_filter, settings.obb)
        loop = PerceptionLoop(session, settings.scan, ready_camera_pose=world.camera_pose())
        world.add_frame_listener(lambda f: loop.on_frame(f, world.q))
        rt = Runtime(world)
        motion = MotionClient(world, MotionPlanner(settings.motion))
        start_q = np.asarray(world.q, float).copy()
        tray = world.data.site(TRAY_SITE).xpos.copy()
        scanner = ActiveScan(rt, loop, motion, flange_T_camera(world.model), settings.scan)
        action = GraspAction(rt, loop, motion, settings.grasp, tray_center=tray, home_q=start_q)
    except BaseException:
        world.close()
        raise
    return System(world, loop, rt, motion, scanner, action, tray, start_q)


def make_scene(scene: str, seed: int, settings: Settings):
    if scene == "reference":
        return reference_scene(settings.sim)
    if scene == "random":
        return random_scene(seed, config=settings.sim)
    raise InputError(f"scene must be 'reference' or 'random', got {scene!r}")


def run_pipeline(scene: str = "reference", seed: int = 0, select: Optional[Sequence[tuple[float, float]]] = None,
                 out_dir: str | Path = "out", json_path: str | Path | None = None,
                 settings: Optional[Settings] = None, video: bool = True, place: bool = True,
                 scan: bool = True) -> dict:
    """Run the whole pipeline headless; returns (and writes) the report."""
    wall0 = time.perf_counter()
    settings = settings or load_settings(SECTIONS)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    spec = make_scene(scene, seed, settings)
    timings: dict[str, float] = {}
    report: dict = {"scene": {"name": spec.name, "seed": seed, "objects": len(spec.objects)},
                    "settings": settings.as_dict()}
    system = build_system(spec, settings)
    world, loop, rt = system.world, system.loop, system.rt
    recorder = None
    try:
        if video:
            recorder = RunRecorder(world, out_dir / "run.mp4")
            rt.observers.append(recorder)
        scanner, action, tray = system.scanner, system.action, system.tray

        # -- rough view -------------------------------------------------------------
        t0 = time.perf_counter()
        rt.spin(ROUGH_VIEW_S)
        timings["rough_view_s"] = time.perf_counter() - t0
        if loop.plane is None:
            report["error"] = "no table plane found from the start pose"
            return report  # (the finally block writes the report)
        report["rough"] = {"tracks": _tracks_report(loop),
                           "scores": scoring.score_estimates(world, loop.tracks(), settings.obb.width_tol_m),
                           "snapshot": _snapshot(loop, out_dir / "rough.png", "rough view (start pose)")}
        rough_tids = {int(t.tid) for t in loop.tracks()}
        report["plane"] = {"normal": [float(x) for x in loop.plane.n], "c": float(loop.plane.c),
                           "height_m": float(loop.plane.height_m)}

        # -- scan -------------------------------------------------------------------
        if scan:
            t0 = time.perf_counter()
            trig = scanner.trigger()
            outcome = rt.run(scanner.task, SCAN_TIMEOUT_S) if trig.accepted else None
            timings["scan_s"] = time.perf_counter() - t0
            rt.spin(SETTLE_VIEW_S)
            report["scan"] = {
                "trigger": trig.message,
                "completed": bool(outcome and outcome.completed),
                "returned_to_start": bool(outcome and outcome.returned_to_start),
                "joint_error_rad": None if outcome is None else outcome.joint_error_rad,
                "failure": "" if outcome is None else outcome.failure,
                "probes": [] if outcome is None else [p.__dict__ for p in outcome.probes],
                "tracks": _tracks_report(loop),
                "scores": scoring.score_estimates(world, loop.tracks(), settings.obb.width_tol_m),
                "snapshot": _snapshot(loop, out_dir / "scan.png", "after the active scan"),
            }

        # -- picks ------------------------------------------------------------------
        t0 = time.perf_counter()
        if select:
            targets = list(select)
        else:
            targets, report["targets_skipped"] = _default_targets(
                loop, WorkCell.from_world(world), settings.grasp.target_fixture_margin_m, rough_tids)
        report["picks"] = [_pick(rt, loop, action, world, xy, settings, tray, place,
                                 scanner if scan else None) for xy in targets]
        timings["picks_s"] = time.perf_counter() - t0
        report["motion_plans"] = system.motion.plans
    finally:
        if recorder is not None:
            report["video"] = recorder.close()
        system.close()
        _finish(report, json_path, wall0, timings)
    return report


def _reprobe_if_needed(rt: Runtime, loop: PerceptionLoop, scanner: ActiveScan, xy, row: dict) -> None:
    """A NADIR track retires ``nadir_hold_s`` after it was last seen (the camera looks at the
    tray while placing), and an oblique view misjudges what a grasp needs. Before a pick,
    measure the object from above again when its track is no longer NADIR, or is gone (ours)."""
    # the track the selection would take (none when the nearest one is beyond its limit)
    chk = check_selection(float(xy[0]), float(xy[1]), loop.tracks(), loop.gate_m, loop.plane,
                          loop.selector.fallback_limit_m)
    track = None if chk.kind in ("far", "nothing") else chk.track
    if track is not None and track.quality == _core.ViewQuality.NADIR:
        return
    if track is not None:
        centre = np.asarray(track.smoothed.center, float)
    elif loop.plane is not None:  # retired and not seen again from here: look where it was
        n, c = np.asarray(loop.plane.n, float), float(loop.plane.c)
        centre = np.array([xy[0], xy[1], -(c + n[0] * xy[0] + n[1] * xy[1]) / n[2]])
    else:
        return
    res = scanner.trigger(centres=[centre])
    if res.accepted:
        out = rt.run(scanner.task, SCAN_TIMEOUT_S)
        row["reprobed"] = bool(out.probes and out.probes[0].nadir)
        rt.spin(SETTLE_VIEW_S)


def _pick(rt: Runtime, loop: PerceptionLoop, action: GraspAction, world, xy, settings, tray, place,
          scanner: Optional[ActiveScan] = None) -> dict:
    rt.spin(SETTLE_VIEW_S)
    row = {"anchor": [float(xy[0]), float(xy[1])], "success": False, "failed_stage": None,
           "message": "", "lift_m": 0.0, "held_s": 0.0, "placed": False}
    if scanner is not None:
        _reprobe_if_needed(rt, loop, scanner, xy, row)
    sel = loop.select(*xy)
    if not sel.ok:
        row.update(failed_stage="SELECT", message=sel.message)
        return row
    # The best grasp must actually arrive (a dead upstream must not look like success).
    n_verify = settings.scan.select_verify_frames
    if not rt.spin_until(lambda: loop.selector.published >= n_verify, settings.scan.stale_timeout_s):
        row.update(failed_stage="SELECT", message=f"selected, but no best grasp arrived within "
                                                  f"{settings.scan.stale_timeout_s} s")
        loop.selector.clear()
        return row
    name = scoring.nearest_truth_name(world, xy)
    lift = scoring.LiftRecorder(name) if name else None
    if lift:
        rt.observers.append(lift)
    track = next((t for t in loop.tracks() if t.tid == sel.tid), None)
    alt = None if track is None else perpendicular_grasp(
        track, loop.plane, settings.obb.gripper_open - settings.grasp.open_margin_m)
    try:
        ok, msg = action.start(place=place, alternatives=() if alt is None else (alt,))
        if not ok:
            row.update(failed_stage="GRASP", message=msg)
            return row
        # The action holds its goal now: stop re-resolving the anchor (once the object is
        # lifted there is nothing left to publish there, and that is no news).
        loop.selector.clear()
        out = rt.run(action.task, PICK_TIMEOUT_S)
    finally:
        loop.selector.clear()
        if lift:
            rt.observers.remove(lift)
    row.update(success=out.success, failed_stage=out.failed_stage, message=out.message or "picked",
               stages=out.stages, stall_gap_m=out.stall_gap_m, width_m=out.width_m,
               selected=sel.message)
    if lift:
        lift.released_at = out.release_time_s
        row.update(lift.result(MIN_LIFT_EVAL_M), object=name)
        half = float(world.model.geom(TRAY_FLOOR_GEOM).size[0])
        row["placed"] = bool(out.placed and scoring.in_tray(world, name, tray, half, tray[2]))
    return row


def _finish(report: dict, json_path, wall0: float, timings: dict) -> dict:
    timings["wall_s"] = time.perf_counter() - wall0
    report["timings"] = timings
    if json_path is not None:
        Path(json_path).parent.mkdir(parents=True, exist_ok=True)
        Path(json_path).write_text(json.dumps(report, indent=2, default=_json_default))
    return report


def _json_default(o):
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, (np.floating, np.integer)):
        return o.item()
    return str(o)
