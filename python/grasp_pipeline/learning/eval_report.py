"""The figures of an ``eval`` run: success rate with its 95 % interval, per task word and per
object, failure reasons, steps and seconds per episode — as the report's dict (``eval.json``)
and as ``summary.md``."""

from __future__ import annotations

import math
from collections import Counter, defaultdict
from statistics import mean, median

#: z of a two-sided 95 % interval.
Z95 = 1.959963984540054


def wilson_interval(successes: int, n: int, z: float = Z95) -> list:
    """The Wilson score interval of a success rate ([low, high]; [0, 1] without episodes)."""
    if n <= 0:
        return [0.0, 1.0]
    p = successes / n
    denom = 1.0 + z * z / n
    centre = (p + z * z / (2 * n)) / denom
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / denom
    return [round(max(0.0, centre - half), 4), round(min(1.0, centre + half), 4)]


def _rate(rows: list[dict]) -> dict:
    k = sum(bool(r["success"]) for r in rows)
    return {"episodes": len(rows), "successes": k, "success_rate": round(k / len(rows), 4) if rows else None,
            "ci95": wilson_interval(k, len(rows))}


def _grouped(rows: list[dict], keys) -> dict:
    groups = defaultdict(list)
    for r in rows:
        for key in keys(r):
            groups[key].append(r)
    return {k: _rate(v) for k, v in sorted(groups.items())}


def failure_reason_key(row: dict) -> str:
    """A failed episode's reason, grouped: the stage and where the target ended."""
    if row.get("error"):
        return "ERROR: " + str(row["error"]).split(":")[0]
    return f"{row.get('failed_stage') or 'UNKNOWN'}: the target is {row.get('target_state') or 'unknown'}"


def figures(rows: list[dict], template: str) -> dict:
    """The report's figures of the finished episodes ``rows`` (:class:`.rollout.EpisodeResult` dicts)."""
    from .targets import task_phrase

    steps = [r["steps"] for r in rows]
    secs = [r["wall_s"] for r in rows]
    overall = {k: v for k, v in _rate(rows).items() if k != "episodes"}
    return {**overall,
            "by_task_word": _grouped(rows, lambda r: sorted(set(task_phrase(r["task"], template).split()))),
            "by_object": _grouped(rows, lambda r: [r["target_model"] or "unknown"]),
            "failure_reasons": dict(Counter(failure_reason_key(r) for r in rows if not r["success"]).most_common()),
            "steps_per_episode": steps, "seconds_per_episode": [round(s, 3) for s in secs],
            "sim_seconds_per_episode": [round(r["sim_s"], 3) for r in rows],
            "mean_steps": round(mean(steps), 1) if steps else None,
            "median_seconds": round(median(secs), 2) if secs else None}


def _table(title: str, groups: dict) -> list[str]:
    lines = [f"## {title}", "", "| | episodes | successes | rate | 95 % interval |", "|---|---|---|---|---|"]
    for k, g in groups.items():
        lines.append(f"| {k} | {g['episodes']} | {g['successes']} | {g['success_rate']:.2f} | "
                     f"{g['ci95'][0]:.2f}–{g['ci95'][1]:.2f} |")
    return lines + [""]


def _or_na(value, unit: str = "") -> str:
    """A figure for the summary: "n/a" when there is none (no finished episode)."""
    return "n/a" if value is None else f"{value}{unit}"


def summary_markdown(report: dict) -> str:
    """``summary.md`` of a report."""
    rate = "n/a" if report.get("success_rate") is None else f"{report['success_rate']:.2f}"
    ci = report.get("ci95", [0, 1])
    lines = [f"# eval: {report['policy']} on {report['protocol']} ({report['objects']})", "",
             f"status **{report['status']}**; {report['episodes_finished']} of {report['episodes_requested']} "
             f"episodes (seed {report['seed']}); success rate **{rate}** "
             f"(95 % interval {ci[0]:.2f}–{ci[1]:.2f}); mean steps {_or_na(report.get('mean_steps'))}, "
             f"median {_or_na(report.get('median_seconds'), ' s')} per episode; wall {report.get('wall_s')} s", ""]
    if report.get("status_note"):
        lines += [f"**{report['status_note']}**", ""]
    if report.get("error"):
        lines += [f"error: {report['error']}", ""]
    lines += _table("By object", report.get("by_object", {}))
    lines += _table("By task word", report.get("by_task_word", {}))
    lines += ["## Failure reasons", ""] + [f"- {n} × {k}" for k, n in report.get("failure_reasons", {}).items()]
    lines += ["", "## Episodes", "", "| # | scene seed | task | success | steps | reason | video |",
              "|---|---|---|---|---|---|---|"]
    for r in report.get("episodes", []):
        video = f"[mp4]({r['video']})" if r.get("video") else ""
        lines.append(f"| {r['index']} | {r['scene_seed']} | {r['task']} | {'yes' if r['success'] else 'no'} | "
                     f"{r['steps']} | {r['failure_reason'].replace('|', '/')} | {video} |")
    return "\n".join(lines) + "\n"
