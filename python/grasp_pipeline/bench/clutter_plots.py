"""Plots (PNG, matplotlib Agg) and the markdown summary of the clutter benchmark.

Input: the JSON form of a :class:`~.clutter_result.ClutterBenchResult` — as a results file
holds it (its ``round_rows`` carry every attempt). Nothing here reads ground truth or runs the
pipeline.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Optional

from .report_text import fmt, md_table, pct, pyplot, short

#: Published results for context (GIGA, Jiang et al. 2021, Table I; EdgeGraspNet's GSR):
#: protocol → [(method, GSR %, DR % or None)].
PUBLISHED = {
    "packed": [("GPD", 35.4, 30.7), ("highest-point heuristic", 56.6, 58.0), ("VGN", 74.5, 79.2),
               ("GIGA", 83.5, 84.3), ("EdgeGraspNet", 92.0, None)],
    "pile": [("GPD", 17.7, 9.2), ("highest-point heuristic", 50.7, 42.6), ("VGN", 60.7, 44.0),
             ("GIGA", 69.3, 49.8), ("EdgeGraspNet", 89.9, None)],
}
SETTING_NOTE = ("Their setting: a free-floating hand and one fixed side view; ours: the whole arm, "
                "planning and placing into a tray.")


def _bar_rates(ax, result: dict) -> None:
    labels = [f"seed {s['seed']}" for s in result["seeds"]] + ["all"]
    gsr = [s["gsr"] or 0.0 for s in result["seeds"]] + [result["gsr"] or 0.0]
    dr = [s["dr"] or 0.0 for s in result["seeds"]] + [result["dr"] or 0.0]
    x = range(len(labels))
    ax.bar([i - 0.2 for i in x], [100 * v for v in gsr], width=0.4, label="GSR")
    ax.bar([i + 0.2 for i in x], [100 * v for v in dr], width=0.4, label="DR")
    for name, g, _d in PUBLISHED.get(result["protocol"], []):
        if name in ("VGN", "GIGA"):
            ax.axhline(g, ls="--", lw=0.8, color="grey")
            ax.text(len(labels) - 0.5, g, f"{name} GSR", fontsize=7, va="bottom", ha="right")
    ax.set_xticks(list(x), labels)
    ax.set_ylim(0, 100)
    ax.set_ylabel("%")
    ax.set_title(f"{result['protocol']} / {Path(result['objects']).name}: GSR and DR")
    ax.legend(loc="lower left")


def _bar_objects(ax, result: dict) -> None:
    groups = result["success_by_object"]
    names = list(groups)
    ax.barh(names, [groups[n]["attempts"] for n in names], color="#dddddd", label="attempts")
    ax.barh(names, [groups[n]["picked"] for n in names], color="#2ca02c", label="picked")
    ax.set_xlabel("count")
    ax.set_title("success by object")
    ax.legend(loc="lower right")
    ax.tick_params(axis="y", labelsize=7)


def _bar_failures(ax, result: dict) -> None:
    f = result["failures_by_stage"]
    ax.bar(list(f), [v["count"] for v in f.values()], color="#d62728")
    ax.set_ylabel("failed attempts")
    ax.set_title("failures by stage")


def write_plots(result: dict, out_dir: str | Path) -> dict[str, Path]:
    """``rates.png``, ``objects.png``, ``failures.png`` in ``out_dir``; name → path."""
    plt = pyplot()
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    paths = {}
    n_obj = max(1, len(result["success_by_object"]))
    for name, draw, size in (("rates", _bar_rates, (6, 4)), ("objects", _bar_objects, (6, 1.5 + 0.22 * n_obj)),
                             ("failures", _bar_failures, (6, 3.5))):
        fig, ax = plt.subplots(figsize=size)
        draw(ax, result)
        fig.tight_layout()
        paths[name] = out / f"{name}.png"
        fig.savefig(paths[name], dpi=100)
        plt.close(fig)
    return paths


def _md_head(r: dict, json_path) -> list[str]:
    L = [f"# Clutter benchmark — {r['protocol']}, objects {r['objects']}", "",
         f"{r['rounds']} rounds (seeds {', '.join(str(s) for s in r['seed_list'])}), {r['workers']} worker(s), "
         f"status {r.get('status', 'complete')}. JSON: `{json_path}`.", ""]
    if r.get("status_note"):
        L += [f"**{r['status_note']}**", ""]
    L += [
         "A round: build the scene, rough view, active scan, then one pick into the tray at a time, "
         "looking again after each attempt; it ends when the table is clear, nothing graspable is "
         "proposed, or after 2 failed attempts in a row. GSR = successful picks / attempts (every "
         "attempt, also one that never moved the arm); DR = successful picks / objects placed. "
         "Std over seeds is the population std.", ""]
    L += md_table(["figure", "value"], [
        ["GSR (all rounds)", pct(r["gsr"])], ["DR (all rounds)", pct(r["dr"])],
        ["GSR mean ± std over seeds", f"{pct(r['mean']['gsr'])} ± {pct(r['std']['gsr'])}"],
        ["DR mean ± std over seeds", f"{pct(r['mean']['dr'])} ± {pct(r['std']['dr'])}"],
        ["GSR of executed attempts (arm reached APPROACH)", pct(r["gsr_executed"])],
        ["objects placed / attempts / picked", f"{r['objects_placed']} / {r['attempts']} / {r['successes']}"],
        ["time per attempt, median [s]", fmt(r["time_per_attempt_s"]["median"], 1)],
        ["time per round, median [s]", fmt(r["time_per_round_s"]["median"], 1)],
        ["rounds per hour", fmt(r["rounds_per_hour"], 1)]])
    L += md_table(["seed", "rounds", "objects", "attempts", "picked", "GSR", "DR"],
                [[s["seed"], s["rounds"], s["objects_placed"], s["attempts"], s["successes"],
                  pct(s["gsr"]), pct(s["dr"])] for s in r["seeds"]])
    return L + ["![rates](rates.png)", ""]


def _md_published(r: dict) -> list[str]:
    L = ["## Published numbers, for context", "", SETTING_NOTE, ""]
    rows = [[m, f"{g:.1f} %", "n/a" if d is None else f"{d:.1f} %"] for m, g, d in PUBLISHED.get(r["protocol"], [])]
    if not rows:
        return L + ["No published numbers for this protocol.", ""]
    L += md_table(["method", "GSR", "DR"], rows + [["**ours (this run)**", pct(r["gsr"]), pct(r["dr"])]])
    return L + ["(GIGA, Jiang et al. 2021, Table I; EdgeGraspNet reports GSR only.)", ""]


BOUND_NAMES = {"top_down": "from straight above", "tilted": "approach tilted ≤ {tilt:.0f}°",
               "any_side": "from some side"}


def _md_grasp_bound(r: dict) -> list[str]:
    """The gap to geometry: label counts, DR against each bound, outcomes per label, reasons."""
    b = r.get("grasp_bound") or {}
    if not b.get("objects"):
        return []
    cfg = b.get("config") or {}
    width = f"{1e3 * cfg['max_width_m']:.0f} mm" if "max_width_m" in cfg else "the configured width"
    tilt = float(cfg.get("tilted_limit_deg", 60.0))
    L = ["## Gap to geometry", "",
         f"Each object is labelled from its true shape and settled pose: graspable by the hand (at most "
         f"{width} between the pads) from straight above, with an approach tilted ≤ {tilt:.0f}° from the "
         "table's normal, from some side, or not at all — each pad touching the object above the table "
         "(*width only*: the widths alone). DR against a bound = objects picked among those graspable "
         "under it / those graspable.", ""]
    n = b["objects"]
    rows = [[f"{k} ({BOUND_NAMES[k].format(tilt=tilt)})", f"{b['graspable'][k]} ({pct(b['graspable_fraction'][k])})",
             pct(b[f"dr_{k}"]), f"{b['graspable_width_only'][k]} ({pct(b['graspable_width_only_fraction'][k])})",
             pct(b["dr_width_only"][k])] for k in BOUND_NAMES]
    rows.append(["all objects", f"{n} (100.0 %)", pct(b["picked"] / n), f"{n}", pct(b["picked"] / n)])
    L += md_table(["bound", "graspable (share)", "DR against it", "width only: graspable", "width only: DR"], rows)
    outcomes = list(b["outcomes"])
    L += ["Outcome of each object by its label (picked objects labelled `none`: "
          f"{b['picked_outside_bound']}):", ""]
    L += md_table(["label", *outcomes, "objects"],
                [[lb, *(b["label_by_outcome"][lb][k] for k in outcomes), sum(b["label_by_outcome"][lb].values())]
                 for lb in b["label_by_outcome"]] + [["all", *(b["outcomes"][k] for k in outcomes), n]])
    for title, key in (("Never proposed: why (the robot's last look)", "never_proposed_reasons"),
                       ("Attempted and failed: stage and reason of the last attempt", "attempted_failed_reasons")):
        if b.get(key):
            L += [f"{title}:", ""] + md_table(["reason", "objects"], [[short(k, 240), v] for k, v in b[key].items()])
    return L


def _md_segmentation_and_ends(r: dict) -> list[str]:
    s = r["segmentation"]
    L = ["## Segmentation at the scan", "",
         "An object is correct when one cluster holds its visible points (above the band) with "
         "≥ 90 % purity and ≥ 80 % coverage, scored in the probe frame whose camera stood nearest it.", ""]
    L += md_table(["objects", "scored", "correct", "correct rate", "merged", "split", "missed"],
                [[s["objects"], s["scored"], s["correct"], pct(s["correct_rate"]), s["merged"], s["split"],
                  s["missed"]]])
    L += ["## How rounds ended", ""]
    return L + md_table(["end", "rounds"], [[k, v] for k, v in r["end_reasons"].items()])


def _md_failures(r: dict) -> list[str]:
    L = ["## Failed attempts", ""]
    f = r["failures_by_stage"]
    L += md_table(["stage", "reason", "attempts"], [[st, reason, n] for st, v in f.items()
                                                  for reason, n in v["reasons"].items()]) if f else ["None.", ""]
    L += ["![failures](failures.png)", "", "| round | scene seed | object | stage | message | PNG |",
          "|---|---|---|---|---|---|"]
    for row in r["round_rows"]:
        for a in row["attempts"]:
            if not a["success"]:
                pngs = " ".join(f"[{Path(p).name}]({os.path.relpath(p, r.get('out_dir', '.'))})"
                                for p in a.get("snapshots") or [])
                L.append(f"| {row['index']} | {row['seed']} | {a['object']} | {a['stage']} | "
                         f"{short(a['message'], 120).replace('|', '/')} | {pngs or '—'} |")
    return L + [""]


def _md_objects(r: dict) -> list[str]:
    L = ["## Success by object", ""]
    L += md_table(["object", "placed", "attempts", "picked", "success"],
                [[k, g["placed"], g["attempts"], g["picked"], pct(g["success_rate"])]
                 for k, g in r["success_by_object"].items()])
    return L + ["![objects](objects.png)", ""]


def _md_rounds(r: dict) -> list[str]:
    L = ["## Rounds", "", f"Reproduce one: `grasp-pipeline run --scene {r['protocol'] if r['protocol'] != 'sparse' else 'random'} "
         f"--objects {r['objects']} --seed <scene seed> --declutter`.", ""]
    return L + md_table(["#", "seed", "scene seed", "objects", "attempts", "picked", "ended", "time [s]"],
                      [[x["index"], x["bench_seed"], x["seed"], x["objects_placed"], len(x["attempts"]),
                        x["successes"], x["end_reason"], fmt(x["timings"].get("wall_s"), 0)]
                       for x in r["round_rows"]])


def write_summary(result: dict, path: str | Path, json_path: Optional[str | Path] = None) -> Path:
    """``summary.md`` of the benchmark (the plots next to it)."""
    L = _md_head(result, json_path)
    for section in (_md_published, _md_grasp_bound, _md_segmentation_and_ends, _md_failures, _md_objects,
                    _md_rounds):
        L += section(result)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join(L))
    return path
