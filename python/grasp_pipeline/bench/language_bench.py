"""How well the language words name the objects of simulated scenes (a measurement, not a test).

For each scene (``packed``/``pile``/``sparse``/``reference`` and seed): build the world, run the
rough view and the active scan as ``run`` does, name every perceived object
(:func:`grasp_pipeline.language.perceive_objects`, which sees no ground truth), then compare
with the truth: the nearest true object (horizontally, within half its smaller side + 2 cm, as
:mod:`grasp_pipeline.evaluation.scoring`) gives the true colour (:func:`colour_name` of its RGBA)
and the true shape word (:data:`TRUE_SHAPE` of its category; anything else is "other").
True objects no track is matched to count as ``missed``.

    grasp-pipeline bench language --scene packed --seeds 0 1 2 --json out.json
"""

from __future__ import annotations

import dataclasses
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional, Sequence

import numpy as np

from ..report.serialize import OMIT_IF_NONE, write_json

#: The shape word a user would use for each object category (ours).
TRUE_SHAPE = {"cube": "box", "cuboid": "box", "rounded_box": "box", "cylinder": "cylinder",
              "can": "cylinder", "mug": "mug", "bottle": "bottle"}


@dataclass(frozen=True, kw_only=True)
class LanguageRow:
    """One true object: its true colour and shape words and the perceived ones (``missed`` when
    no track matched it; then no ``tid``, ``rgb`` or ``features``)."""

    scene: str
    seed: int
    object: str
    category: str
    true_colour: str
    true_shape: str
    colour: str = "missed"
    shape: str = "missed"
    tid: Optional[int] = None
    rgb: Optional[tuple[float, ...]] = field(default=None, metadata=OMIT_IF_NONE)
    features: Optional[dict] = field(default=None, metadata=OMIT_IF_NONE)


@dataclass(frozen=True)
class LanguageBenchResult:
    """Every true object's row, the confusion of the words (true word → {perceived word:
    count}) and the CPU time it took [s]."""

    rows: tuple[LanguageRow, ...]
    colour: dict[str, dict[str, int]]
    shape: dict[str, dict[str, int]]
    cpu_s: float


def _look(system, settings) -> None:
    """Rough view, active scan, settle view (as ``run``)."""
    system.rt.spin(settings.scan.rough_view_s)
    trig = system.scanner.trigger()
    if trig.accepted:
        system.rt.run(system.scanner.task, settings.scan.scan_timeout_s)
    system.rt.spin(settings.scan.settle_view_s)


def _perceived(scene: str, seed: int, settings):
    """(scene spec, perceived objects, true objects by name) after the look."""
    from ..app.sim_system import build_system, make_scene
    from ..language import ObservationRecorder, perceive_objects
    from ..sim.ground_truth import object_truths

    spec = make_scene(scene, seed, settings)
    system = build_system(spec, settings)
    try:
        obs = ObservationRecorder(settings.language).attach(system.events)
        _look(system, settings)
        margin = settings.grasp.target_fixture_margin_m
        tracks = [t for t in system.loop.tracks()
                  if system.cell.pick_target_note(t.smoothed.center[:2], margin) is None]
        objects = perceive_objects(tracks, obs, settings.language)
        truths = {t.name: t for t in object_truths(system.world)}
    finally:
        system.close()
    return spec, objects, truths


def scene_rows(scene: str, seed: int, settings) -> list[LanguageRow]:
    """One row per true object: true and perceived colour/shape (``missed`` when no track)."""
    from ..language import colour_name

    spec, objects, truths = _perceived(scene, seed, settings)
    rows = []
    for o in spec.objects:
        t = truths[o.name]
        row = LanguageRow(scene=scene, seed=seed, object=o.name, category=o.category or o.kind,
                          true_colour=colour_name(o.rgba[:3], settings.language),
                          true_shape=TRUE_SHAPE.get(o.category or o.kind, "other"))
        d = [np.hypot(*(np.asarray(p.center_m[:2]) - t.position_m[:2])) for p in objects]
        if d and min(d) < 0.5 * min(t.size_m[:2]) + 0.02:
            p = objects[int(np.argmin(d))]
            row = dataclasses.replace(row, colour=p.colour, shape=p.shape, tid=p.tid, rgb=p.rgb,
                                      features=None if p.features is None else dataclasses.asdict(p.features))
        rows.append(row)
    return rows


def confusion(rows: Sequence[LanguageRow], key: str) -> dict[str, dict[str, int]]:
    """true word → {perceived word: count} (``key``: ``colour`` or ``shape``)."""
    out: dict[str, Counter] = {}
    for r in rows:
        out.setdefault(getattr(r, f"true_{key}"), Counter())[getattr(r, key)] += 1
    return {k: dict(sorted(v.items())) for k, v in sorted(out.items())}


def run_language_benchmark(scenes: Sequence[str] = ("packed",), seeds: Sequence[int] = (0,),
                           json_path: str | Path | None = None,
                           overrides: tuple = (None, ())) -> LanguageBenchResult:
    """Every scene of ``scenes`` with every seed of ``seeds``; ``overrides``: ``(config_file,
    [name=value, ...])`` for the settings. Writes the JSON (if ``json_path``)."""
    from ..app.sim_system import SECTIONS
    from ..report.serialize import check_writable
    from ..settings import load_settings

    settings = load_settings(SECTIONS, overrides[0], list(overrides[1]))
    if json_path is not None:
        check_writable(json_path, "benchmark JSON (--json)")
    rows, cpu0 = [], time.process_time()
    for scene in scenes:
        for seed in seeds:
            rows += scene_rows(scene, seed, settings)
    result = LanguageBenchResult(rows=tuple(rows), colour=confusion(rows, "colour"),
                                 shape=confusion(rows, "shape"), cpu_s=time.process_time() - cpu0)
    if json_path is not None:
        write_json(json_path, result)
    return result


def _table(conf: dict[str, dict[str, int]]) -> str:
    lines = []
    for true, row in conf.items():
        n = sum(row.values())
        lines.append(f"  {true:9s} ({row.get(true, 0)}/{n} right): "
                     + ", ".join(f"{k} {v}" for k, v in row.items()))
    return "\n".join(lines)


def summary_text(result: LanguageBenchResult, scenes: Sequence[str], seeds: Sequence[int]) -> str:
    """What the command prints: the counts and both confusion tables."""
    return "\n".join([
        f"{len(result.rows)} objects, scenes {list(scenes)} seeds {list(seeds)}, CPU {result.cpu_s:.0f} s",
        "colour (true: perceived counts)\n" + _table(result.colour),
        "shape (true: perceived counts)\n" + _table(result.shape)])
