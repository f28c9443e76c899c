"""The ``run`` command's front end: argument checks, the run, a short printed summary."""

from __future__ import annotations

import logging
from pathlib import Path

from ..exceptions import InputError
from ..settings import load_settings

log = logging.getLogger("grasp_pipeline.run")


def parse_select(values) -> list[tuple[float, float]] | None:
    if values is None:
        return None
    if len(values) % 2:
        raise InputError(f"--select takes (x, y) pairs; got {len(values)} numbers")
    return [(float(values[i]), float(values[i + 1])) for i in range(0, len(values), 2)]


def summarize(report: dict) -> str:
    lines = []
    if "plane" in report:
        lines.append(f"table plane at z = {report['plane']['height_m']:.4f} m")
    if "error" in report:
        lines.append(f"error: {report['error']}")
    scan = report.get("scan")
    if scan:
        lines.append(f"scan: {scan['trigger']}; completed {scan['completed']}, back at start "
                     f"{scan['returned_to_start']} (joint error {scan['joint_error_rad']})")
        for t in scan["tracks"]:
            lines.append(f"  #{t['tid']} {t['quality'].lower():7s} pca_tilt {t['pca_tilt_deg']:5.1f} deg  "
                         f"centre ({t['center'][0]:.3f}, {t['center'][1]:.3f}, {t['center'][2]:.3f})  "
                         f"extents {t['extents'][0] * 1e3:.1f} x {t['extents'][1] * 1e3:.1f} x "
                         f"{t['extents'][2] * 1e3:.1f} mm")
    for p in report.get("picks", []):
        status = "picked" if p["success"] else f"FAILED at {p['failed_stage']}"
        lines.append(f"pick ({p['anchor'][0]:.3f}, {p['anchor'][1]:.3f}): {status}; lifted "
                     f"{p['lift_m'] * 1e3:.0f} mm, held {p['held_s']:.1f} s, in tray {p['placed']}"
                     + ("" if p["success"] else f" — {p['message']}"))
    t = report.get("timings", {})
    if t:
        lines.append("wall time: " + ", ".join(f"{k} {v:.1f}" for k, v in t.items()))
    return "\n".join(lines)


def run_command(args) -> int:
    from .run import SECTIONS, run_pipeline

    select = parse_select(args.select)
    settings = load_settings(SECTIONS, args.config, args.sets)
    out = Path(args.out)
    json_path = args.json or out / "report.json"
    report = run_pipeline(scene=args.scene, seed=args.seed, select=select, out_dir=out,
                          json_path=json_path, settings=settings, video=not args.no_video,
                          scan=not args.no_scan)
    print(summarize(report))
    print(f"report: {json_path}")
    for key, label in (("rough", "rough-view snapshot"), ("scan", "after-scan snapshot")):
        if report.get(key, {}).get("snapshot"):
            print(f"{label}: {report[key]['snapshot']}")
    if report.get("video"):
        print(f"video: {report['video']}")
    picks = report.get("picks", [])
    return 0 if picks and all(p["success"] for p in picks) else 1
