"""The ``run`` and ``demo`` commands' front end: argument checks, the run, a printed summary.

Every number from the command line is checked here (finite, pairs), and every output path
before the simulation starts. SIGTERM is turned into the same clean stop as Ctrl-C: the arm
holds and the report is written with ``"status": "interrupted"``.
"""

from __future__ import annotations

import logging
import math
import sys
from pathlib import Path

from ..exceptions import InputError
from ..report.serialize import to_jsonable
from ..settings import load_settings
from ..signals import interrupts_raise

log = logging.getLogger("grasp_pipeline.run")


def parse_select(values) -> list[tuple[float, float]] | None:
    """``--select X Y ...`` → [(x, y), ...]; pairs of finite numbers [m]."""
    if values is None:
        return None
    if len(values) % 2:
        raise InputError(f"--select takes (x, y) pairs; got {len(values)} numbers")
    bad = [v for v in values if not math.isfinite(float(v))]
    if bad:
        raise InputError(f"--select: coordinates must be finite numbers in metres, got {bad[0]}")
    return [(float(values[i]), float(values[i + 1])) for i in range(0, len(values), 2)]


def parse_pick(values, select, declutter: bool, language_config=None) -> list[str]:
    """``--pick DESCRIPTION`` (repeatable) → the descriptions; not with --select/--declutter.
    Each is read now (unknown words are refused before the simulation starts); which object
    it names is decided after the scan."""
    if not values:
        return []
    if select is not None or declutter:
        raise InputError("--pick names the objects to pick; it cannot be combined with "
                         f"{'--select' if select is not None else '--declutter'} (use one of them)")
    empty = [v for v in values if not v.strip()]
    if empty:
        raise InputError('--pick: an empty description; describe the object, e.g. --pick "the red mug"')
    from ..language import parse

    for v in values:
        parse(v, language_config)
    return [v.strip() for v in values]


def _scan_lines(scan: dict) -> list[str]:
    lines = [f"scan: {scan['trigger']}; completed {scan['completed']}, back at start "
             f"{scan['returned_to_start']} (joint error {scan['joint_error_rad']})"]
    for t in scan["tracks"]:
        c, e = t["center"], t["extents"]
        lines.append(f"  #{t['tid']} {t['quality'].lower():7s} pca_tilt {t['pca_tilt_deg']:5.1f} deg  "
                     f"centre ({c[0]:.3f}, {c[1]:.3f}, {c[2]:.3f})  extents {e[0] * 1e3:.1f} x "
                     f"{e[1] * 1e3:.1f} x {e[2] * 1e3:.1f} mm")
    return lines


def summarize(report: dict) -> str:
    """A few lines for the console: plane, scan, each pick, skipped tracks, timings."""
    lines = [f"status: {report.get('status')}"]
    if report.get("plane"):
        lines.append(f"table plane at z = {report['plane']['height_m']:.4f} m")
    if report.get("error"):
        lines.append(f"error: {report['error']}")
    if report.get("scan"):
        lines += _scan_lines(report["scan"])
    for s in report.get("targets_skipped", []):
        lines.append(f"not picked: track #{s['tid']} at ({s['center'][0]:.3f}, {s['center'][1]:.3f}): {s['why']}")
    for r in report.get("resolved", []):
        lines.append(f"{r['description']!r}: #{r['tid']}, {r['described']} at "
                     f"({r['center'][0]:.3f}, {r['center'][1]:.3f})")
    for p in report.get("picks", []):
        status = "picked" if p["success"] else f"FAILED at {p['failed_stage']}"
        lines.append(f"pick ({p['anchor'][0]:.3f}, {p['anchor'][1]:.3f}): {status}; lifted "
                     f"{p['lift_m'] * 1e3:.0f} mm, held {p['held_s']:.1f} s, in tray {p['placed']}"
                     + ("" if p["success"] else f" — {p['message']}"))
    for w in report.get("warnings", []):
        lines.append(f"warning: {w}")
    t = report.get("timings", {})
    if t:
        wall = {k: v for k, v in t.items() if v is not None and not _is_sim_figure(k)}
        lines.append("wall time: " + ", ".join(f"{k} {v:.1f}" for k, v in wall.items()))
        sim = {k: v for k, v in t.items() if v is not None and _is_sim_figure(k)}
        if sim:
            lines.append("simulated: " + ", ".join(f"{k} {v:.1f}" for k, v in sim.items()))
    return "\n".join(lines)


def _is_sim_figure(key: str) -> bool:
    """Timings keys that are simulated seconds or real-time factors, not wall seconds."""
    return key.endswith("_sim_s") or key.endswith("_real_time_factor")


def sigterm_as_interrupt():
    """Within the block, SIGTERM raises KeyboardInterrupt like Ctrl-C (main thread only); both
    are counted (:mod:`grasp_pipeline.signals`: a signal a library swallows is raised again)."""
    return interrupts_raise()


def run_command(args, scene: str | None = None) -> int:
    """Run (``args`` from the ``run``/``demo`` parser); exit code 0 when every pick succeeded,
    1 when a pick failed or nothing was picked, 130 when interrupted."""
    from .run import run_pipeline
    from .sim_system import SECTIONS

    select = parse_select(args.select)
    settings = load_settings(SECTIONS, args.config, args.sets)
    pick = parse_pick(getattr(args, "pick", None), select, getattr(args, "declutter", False),
                      settings.language)
    out = Path(args.out)
    json_path = args.json or out / "report.json"
    with sigterm_as_interrupt():
        report = run_pipeline(scene=scene or args.scene, seed=args.seed, select=select, out_dir=out,
                              json_path=json_path, settings=settings, video=not args.no_video,
                              scan=not args.no_scan, objects=getattr(args, "objects", "builtin"),
                              declutter=getattr(args, "declutter", False), pick=pick,
                              rerun=getattr(args, "rerun", None))
    data = to_jsonable(report)
    print(summarize(data))
    print(f"report: {json_path}")
    for key, label in (("rough", "rough-view snapshot"), ("scan", "after-scan snapshot")):
        if (data.get(key) or {}).get("snapshot"):
            print(f"{label}: {data[key]['snapshot']}")
    if data.get("video"):
        print(f"video: {data['video']}")
    if data.get("recording"):
        print(f"Rerun recording: {data['recording']} (open with: rerun {data['recording']})")
    if report.status == "interrupted":
        return 130
    if report.status == "failed" and report.error:
        print(f"error: {report.error}", file=sys.stderr)
    return 0 if report.all_picked else 1
