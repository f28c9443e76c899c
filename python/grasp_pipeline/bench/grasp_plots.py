"""Plots (PNG, matplotlib Agg) and the markdown summary of the grasp benchmark.

Input: the JSON form of a :class:`~.grasp_result.GraspBenchResult` — as a results file holds
it, so a loaded file is drawn the same way (its ``scene_rows`` carry the per-object errors,
outcomes and timings). Nothing here reads ground truth or runs the pipeline.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Optional

from .accuracy import ACCURACY_METRICS, YAW_KINDS
from .report_text import fmt, md_table, pct, pyplot, short

#: Accuracy panels: (JSON metric, axis label, NADIR target or None).
ERROR_PANELS = (
    ("center_mm", "centre error [mm]", 2.0),
    ("width_mm", "width error [mm]", 1.5),
    ("height_mm", "height error [mm]", 1.5),
    ("yaw_deg", "yaw error [deg] (cubes, cuboids)", 1.5),
    ("pca_tilt_deg", "PCA tilt [deg]", None),
)
PANEL_TITLES = {"center_mm": "Box centre error", "width_mm": "Width error (grasp side)",
                "height_mm": "Height error", "yaw_deg": "Yaw error (cubes, cuboids)",
                "pca_tilt_deg": "PCA tilt from the table normal"}
#: Stage timings drawn in the time breakdown (report["timings"] keys), in run order.
TIME_STAGES = (("rough_view_s", "rough view"), ("scan_s", "scan"), ("picks_s", "picks"))
NADIR_COLOR = "#1f77b4"
OBLIQUE_COLOR = "#ff7f0e"


def _objects(result: dict) -> list[dict]:
    return [o for r in result.get("scene_rows", []) for o in r["object_rows"]]


def _errors(result: dict, metric: str, nadir: bool) -> list[float]:
    field = ACCURACY_METRICS[metric]
    out = []
    for o in _objects(result):
        e = o.get("nadir_errors" if nadir else "rough_errors")
        if not e or (nadir and e.get("quality") != "NADIR"):
            continue
        if metric == "yaw_deg" and o["kind"] not in YAW_KINDS:
            continue
        v = e.get(field)
        if v is not None and math.isfinite(v):
            out.append(float(v))
    return out


def _median(v: list[float]) -> Optional[float]:
    if not v:
        return None
    s = sorted(v)
    n = len(s)
    return s[n // 2] if n % 2 else 0.5 * (s[n // 2 - 1] + s[n // 2])


def plot_errors(result: dict, path: Path) -> Path:
    """Histograms of the estimate errors, NADIR (after the scan) over oblique (rough view)."""
    import numpy as np

    plt = pyplot()
    from matplotlib.ticker import MaxNLocator

    fig, axes = plt.subplots(2, 3, figsize=(15, 8.5))
    for ax, (metric, label, target) in zip(axes.flat, ERROR_PANELS):
        nad, obl = _errors(result, metric, True), _errors(result, metric, False)
        both = nad + obl
        if not both:
            ax.text(0.5, 0.5, "no data", ha="center", va="center", transform=ax.transAxes)
        else:
            hi = float(np.percentile(both, 98)) if len(both) > 5 else max(both)
            hi = max(hi, 1e-3, (target or 0.0) * 1.2)
            bins = np.linspace(0.0, hi, 26)
            clip = lambda v: np.clip(v, 0.0, hi)  # noqa: E731  (outliers in the last bin)
            for vals, name, color in ((obl, "oblique (rough view)", OBLIQUE_COLOR),
                                      (nad, "NADIR (after scan)", NADIR_COLOR)):
                if vals:
                    med = _median(vals)
                    ax.hist(clip(vals), bins=bins, alpha=0.55, color=color,
                            label=f"{name}: n={len(vals)}, median {med:.2f}")
                    ax.axvline(med, color=color, lw=1.5, ls="--")
            if target is not None:
                ax.axvline(target, color="k", lw=1.2, ls=":", label=f"NADIR target (median) {target}")
            ax.legend(fontsize=8)
        ax.set_xlabel(label)
        ax.set_ylabel("objects")
        ax.set_title(PANEL_TITLES[metric])
        ax.yaxis.set_major_locator(MaxNLocator(integer=True))
        ax.grid(alpha=0.3)
    ax = axes.flat[-1]
    ax.axis("off")
    acc, obl = result.get("accuracy", {}), result.get("accuracy_oblique", {})
    lines = ["median / p90", ""]
    for metric, label, _t in ERROR_PANELS:
        a, b = acc.get(metric, {}), obl.get(metric, {})
        lines.append(f"{label.split(' (')[0]}")
        lines.append(f"   NADIR   {fmt(a.get('median'))} / {fmt(a.get('p90'))}")
        lines.append(f"   oblique {fmt(b.get('median'))} / {fmt(b.get('p90'))}")
    ax.text(0.0, 1.0, "\n".join(lines), va="top", family="monospace", fontsize=9, transform=ax.transAxes)
    fig.suptitle(f"Estimate errors vs ground truth — {result.get('objects', 0)} objects in "
                 f"{result.get('scenes', 0)} scenes (outliers drawn in the last bin)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _success_bars(ax, groups: dict, title: str, xlabel: str) -> None:
    names = list(groups)
    rates = [100.0 * (groups[k]["success_rate"] or 0.0) for k in names]
    bars = ax.bar(names, rates, color=["#2ca02c" if r >= 95 else "#d62728" for r in rates])
    for b, k in zip(bars, names):
        g = groups[k]
        ax.text(b.get_x() + b.get_width() / 2, b.get_height() + 1.5, f"{g['picked']}/{g['objects']}",
                ha="center", va="bottom", fontsize=9)
    ax.axhline(95.0, color="k", ls=":", lw=1.2, label="target 95 %")
    ax.set_ylim(0, 112)
    ax.set_ylabel("objects picked into the tray [%]")
    ax.set_xlabel(xlabel)
    ax.set_title(title)
    ax.legend(fontsize=8, loc="lower right")
    ax.grid(axis="y", alpha=0.3)


def plot_success(result: dict, path: Path) -> Path:
    """Pick success by object type, by width, by number of objects in the scene."""
    plt = pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.8))
    _success_bars(axes[0], result.get("success_by_kind", {}), "Success by object type", "object type")
    _success_bars(axes[1], result.get("success_by_width_mm", {}), "Success by object width",
                  "true width (narrow horizontal side) [mm]")
    _success_bars(axes[2], result.get("success_by_scene_objects", {}), "Success by scene crowding",
                  "objects in the scene")
    fig.suptitle(f"Pick success: {result.get('picked', 0)}/{result.get('objects', 0)} objects "
                 f"({pct(result.get('success_rate'))})")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot_failures(result: dict, path: Path) -> Path:
    """Failed objects by stage and reason."""
    import textwrap

    from matplotlib.ticker import MaxNLocator

    plt = pyplot()
    items = [(textwrap.fill(f"{stage}: {reason}", 48), n)
             for stage, f in result.get("failures_by_stage", {}).items() for reason, n in f["reasons"].items()]
    fig, ax = plt.subplots(figsize=(11, max(3.0, 0.6 * len(items) + 1.5)))
    if items:
        labels, counts = zip(*reversed(items))
        y = range(len(labels))
        ax.barh(list(y), counts, color="#d62728")
        ax.set_yticks(list(y), labels, fontsize=9)
        for yy, c in zip(y, counts):
            ax.text(c, yy, f" {c}", va="center", fontsize=9)
        ax.set_xlim(0, max(counts) * 1.15 + 0.5)
    else:
        ax.text(0.5, 0.5, "no failed objects", ha="center", va="center", transform=ax.transAxes, fontsize=14)
        ax.set_yticks([])
    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.set_xlabel("failed objects")
    ax.grid(axis="x", alpha=0.3)
    fig.suptitle(f"Failures by stage and reason — {result.get('failures', 0)} of "
                 f"{result.get('objects', 0)} objects not picked into the tray")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot_timing(result: dict, path: Path) -> Path:
    """Time per scene split by stage, and scene time vs number of objects."""
    import numpy as np

    plt = pyplot()
    rows = result.get("scene_rows", [])
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.8), gridspec_kw={"width_ratios": [2.2, 1, 1.2]})
    ax = axes[0]
    x = np.arange(len(rows))
    bottom = np.zeros(len(rows))
    colors = ("#9467bd", "#1f77b4", "#2ca02c", "#7f7f7f")
    for (key, label), color in zip(TIME_STAGES + (("other", "set-up, reports, other"),), colors):
        if key == "other":
            vals = np.array([max(0.0, (r["timings"].get("wall_s") or 0.0) - sum(
                r["timings"].get(k) or 0.0 for k, _ in TIME_STAGES)) for r in rows])
        else:
            vals = np.array([r["timings"].get(key) or 0.0 for r in rows])
        ax.bar(x, vals, bottom=bottom, color=color, label=label, width=0.85)
        bottom += vals
    ax.set_xlabel("scene (index; label: objects)")
    ax.set_ylabel("wall time [s]")
    ax.set_title("Time per scene by stage")
    if len(rows) <= 40:
        ax.set_xticks(x, [f"{r['index']}\n({r['objects']})" for r in rows], fontsize=8)
    ax.legend(fontsize=8)
    ax.grid(axis="y", alpha=0.3)

    ax = axes[1]
    stages = [(k, lbl) for k, lbl in TIME_STAGES if k in result.get("time_per_stage_s", {})]
    med = [result["time_per_stage_s"][k]["median"] or 0.0 for k, _ in stages]
    p90 = [result["time_per_stage_s"][k]["p90"] or 0.0 for k, _ in stages]
    xs = np.arange(len(stages))
    ax.bar(xs - 0.2, med, 0.4, label="median", color="#1f77b4")
    ax.bar(xs + 0.2, p90, 0.4, label="p90", color="#aec7e8")
    ax.set_xticks(xs, [lbl for _, lbl in stages])
    ax.set_ylabel("wall time per scene [s]")
    ax.set_title("Stage time over scenes")
    ax.legend(fontsize=8)
    ax.grid(axis="y", alpha=0.3)

    ax = axes[2]
    n = [r["objects"] for r in rows]
    w = [r["timings"].get("wall_s") or 0.0 for r in rows]
    ax.scatter(n, w, c=["#d62728" if r["picks"] < r["objects"] else "#2ca02c" for r in rows], s=25)
    ax.set_xlabel("objects in the scene")
    ax.set_ylabel("scene wall time [s]")
    ax.set_title("Scene time vs objects (red: a failure)")
    from matplotlib.ticker import MaxNLocator

    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.grid(alpha=0.3)
    fig.suptitle(f"Timing — {result.get('scenes', 0)} scenes in {result.get('wall_time_s', 0):.0f} s wall with "
                 f"{result.get('workers', 1)} worker(s): {result.get('scenes_per_minute') or 0:.2f} scenes/min")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def write_plots(result: dict, out_dir: str | Path) -> dict:
    """All plots into ``out_dir``; returns {name: path}."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    return {"errors": plot_errors(result, out / "errors.png"),
            "success": plot_success(result, out / "success.png"),
            "failures": plot_failures(result, out / "failures.png"),
            "timing": plot_timing(result, out / "timing.png")}


# ------------------------------------------------------------------------------ markdown
def _md_intro(r: dict, json_path: Optional[str | Path]) -> list[str]:
    """Title and the paragraph saying what a scene runs."""
    L = [f"# Grasp benchmark — {r['scenes']} scenes, seed {r['seed']}", ""]
    L += [f"Every scene: rough view, active scan, pick every object into the tray "
          f"(`run_pipeline(scene=\"random\", seed=<scene seed>)`). Ground truth is used for scoring only. "
          f"{r['workers']} worker process(es), MuJoCo GL `{r.get('mujoco_gl', '?')}`."
          + (f" Full figures: `{json_path}`." if json_path else "")
          + f" Status {r.get('status', 'complete')}.", ""]
    if r.get("status_note"):
        L += [f"**{r['status_note']}**", ""]
    return L


def _md_headline(r: dict) -> list[str]:
    L = ["## Headline", ""]
    L += md_table(["figure", "value"], [
        ["scenes (raised)", f"{r['scenes']} ({r['scenes_failed']})"],
        ["objects", r["objects"]],
        ["picked into the tray", f"{r['picked']} ({pct(r['success_rate'])})"],
        ["pipeline-reported pick success (per attempt)", pct(r.get("reported_success_rate"))],
        ["reported success but not in the tray", r.get("false_successes", 0)],
        ["objects reaching NADIR in the scan", pct(r["scan_success_rate"])],
        ["time per scene (median / p90)", f"{fmt(r['time_per_scene_s']['median'], 1)} / "
                                          f"{fmt(r['time_per_scene_s']['p90'], 1)} s"],
        ["time per object (median)", f"{fmt(r['time_per_object_s']['median'], 1)} s"],
        ["wall time", f"{r['wall_time_s']:.1f} s"],
        ["throughput", f"{fmt(r['scenes_per_minute'], 2)} scenes/min"],
        ["real-time factor (run / pick loop)",
         f"{fmt((r.get('real_time_factor') or {}).get('run'), 1)} / "
         f"{fmt((r.get('real_time_factor') or {}).get('pick_loop'), 1)}"],
    ])
    return L


def _md_targets(r: dict) -> list[str]:
    L = ["## Targets", ""]
    L += md_table(["target", "value", "required", "met"], [
        [k, fmt(v["value"], 3), v["target"], {True: "yes", False: "**no**", None: "n/a"}[v["met"]]]
        for k, v in r.get("targets", {}).items()])
    return L


def _md_scan_improvement(r: dict) -> list[str]:
    """Oblique vs NADIR medians on the objects that have both estimates."""
    L = ["## What the scan buys: oblique (rough view) vs NADIR (after the scan)", "",
         f"Same {r['scan_improvement']['objects']} objects (those with both estimates); medians.", ""]
    rows = []
    for metric, label, _t in ERROR_PANELS:
        s = r["scan_improvement"][metric]
        o, n = s["oblique_median"], s["nadir_median"]
        gain = "n/a" if o is None or n is None or n <= 0 else f"{o / n:.1f}×"
        rows.append([label, fmt(o), fmt(n), gain])
    L += md_table(["error", "oblique", "NADIR", "oblique / NADIR"], rows)
    return L


def _md_accuracy(r: dict) -> list[str]:
    L = ["## Accuracy (all objects)", ""]
    rows = []
    for metric, label, _t in ERROR_PANELS:
        a, b = r["accuracy"][metric], r["accuracy_oblique"][metric]
        rows.append([label, fmt(a["median"]), fmt(a["p90"]), a["n"], fmt(b["median"]), fmt(b["p90"]), b["n"]])
    L += md_table(["error", "NADIR median", "NADIR p90", "n", "oblique median", "oblique p90", "n"], rows)
    L += ["Yaw is scored for cubes and cuboids: modulo 90° for cubes and for cuboids whose sides "
          "differ by no more than perception's `obb.width_tol_m` (two equivalent closing directions, "
          "method.md §2.3; their width is compared with the side the estimate closes on), modulo 180° "
          "for the other cuboids.", ""]
    L += ["![estimate errors](errors.png)", ""]
    return L


def _md_failures(r: dict) -> list[str]:
    L = ["## Failures", ""]
    if r["failures_by_stage"]:
        L += md_table(["stage", "reason", "objects"],
                    [[s, reason, n] for s, f in r["failures_by_stage"].items() for reason, n in f["reasons"].items()])
    else:
        L += ["No failed objects.", ""]
    if r.get("scan_failures"):
        L += ["Scan failures (the objects may still have been picked):", ""]
        L += md_table(["scan failure", "scenes"], [[k, v] for k, v in r["scan_failures"].items()])
    L += ["![failures](failures.png)", ""]
    return L


def _md_success(r: dict) -> list[str]:
    L = ["## Success by object type and size", ""]
    L += md_table(["group", "picked / objects", "success"],
                [[f"type {k}", f"{g['picked']}/{g['objects']}", pct(g["success_rate"])]
                 for k, g in r["success_by_kind"].items()]
                + [[f"width {k} mm", f"{g['picked']}/{g['objects']}", pct(g["success_rate"])]
                   for k, g in r["success_by_width_mm"].items()])
    L += ["![success](success.png)", ""]
    return L


def _md_time(r: dict) -> list[str]:
    L = ["## Time", ""]
    L += md_table(["stage", "median [s]", "p90 [s]", "mean [s]"],
                [[k, fmt(v["median"], 1), fmt(v["p90"], 1), fmt(v["mean"], 1)]
                 for k, v in r["time_per_stage_s"].items()])
    L += ["![timing](timing.png)", ""]
    return L


def _md_scenes(r: dict) -> list[str]:
    L = ["## Scenes", "", "Reproduce one: `grasp-pipeline run --scene random --seed <seed>`.", ""]
    L += md_table(["#", "seed", "objects", "picked", "time [s]", "errors"],
                [[s["index"], s["seed"], s["objects"], s["picks"], fmt(s["timings"].get("wall_s"), 1),
                  "; ".join(short(e) for e in s["errors"]) or "—"] for s in r["scene_rows"]])
    return L


def summary_markdown(result: dict, json_path: Optional[str | Path] = None) -> str:
    r = result
    L = _md_intro(r, json_path)
    for section in (_md_headline, _md_targets, _md_scan_improvement, _md_accuracy, _md_failures,
                    _md_success, _md_time, _md_scenes):
        L += section(r)
    return "\n".join(L)


def write_summary(result: dict, path: str | Path, json_path: Optional[str | Path] = None) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(summary_markdown(result, json_path))
    return path


__all__ = ["write_plots", "write_summary", "summary_markdown"]
