"""How well the language words name the objects of simulated scenes (a measurement, not a test).

For each scene (``packed``/``pile``/``sparse``/``reference`` and seed): build the world, run the
rough view and the active scan as ``run`` does, name every perceived object
(:func:`grasp_pipeline.language.perceive_objects`, which sees no ground truth), then compare
with the truth: the nearest true object (horizontally, within half its smaller side + 2 cm, as
:mod:`grasp_pipeline.evaluation.scoring`) gives the true colour (:func:`colour_name` of its RGBA)
and the true shape word (:data:`TRUE_SHAPE` of its category; anything else is "other").
True objects no track is matched to count as ``missed``.

    python -m grasp_pipeline.bench.language_bench --scene packed --seeds 0 1 2 --json out.json
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
import time
from collections import Counter

import numpy as np

#: The shape word a user would use for each object category (ours).
TRUE_SHAPE = {"cube": "box", "cuboid": "box", "rounded_box": "box", "cylinder": "cylinder",
              "can": "cylinder", "mug": "mug", "bottle": "bottle"}


def _look(system, settings) -> None:
    """Rough view, active scan, settle view (as ``run``)."""
    system.rt.spin(settings.scan.rough_view_s)
    trig = system.scanner.trigger()
    if trig.accepted:
        system.rt.run(system.scanner.task, settings.scan.scan_timeout_s)
    system.rt.spin(settings.scan.settle_view_s)


def scene_rows(scene: str, seed: int, settings) -> list[dict]:
    """One row per true object: true and perceived colour/shape (``missed`` when no track)."""
    from ..app.sim_system import build_system, make_scene
    from ..language import ObservationRecorder, colour_name, perceive_objects
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
    rows = []
    for o in spec.objects:
        t = truths[o.name]
        row = {"scene": scene, "seed": seed, "object": o.name, "category": o.category or o.kind,
               "true_colour": colour_name(o.rgba[:3], settings.language),
               "true_shape": TRUE_SHAPE.get(o.category or o.kind, "other"), "colour": "missed",
               "shape": "missed", "tid": None}
        d = [np.hypot(*(np.asarray(p.center_m[:2]) - t.position_m[:2])) for p in objects]
        if d and min(d) < 0.5 * min(t.size_m[:2]) + 0.02:
            p = objects[int(np.argmin(d))]
            row.update(colour=p.colour, shape=p.shape, tid=p.tid, rgb=p.rgb,
                       features=None if p.features is None else dataclasses.asdict(p.features))
        rows.append(row)
    return rows


def confusion(rows: list[dict], key: str) -> dict[str, dict[str, int]]:
    """true word → {perceived word: count}."""
    out: dict[str, Counter] = {}
    for r in rows:
        out.setdefault(r[f"true_{key}"], Counter())[r[key]] += 1
    return {k: dict(sorted(v.items())) for k, v in sorted(out.items())}


def _table(conf: dict[str, dict[str, int]]) -> str:
    lines = []
    for true, row in conf.items():
        n = sum(row.values())
        lines.append(f"  {true:9s} ({row.get(true, 0)}/{n} right): "
                     + ", ".join(f"{k} {v}" for k, v in row.items()))
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", nargs="+", default=["packed"])
    ap.add_argument("--seeds", nargs="+", type=int, default=[0])
    ap.add_argument("--json", default=None)
    args = ap.parse_args(argv)
    from ..sim.gl_backend import configure_gl

    configure_gl()  # as the console commands: GL colour images when a context can be made
    from ..app.sim_system import SECTIONS
    from ..settings import load_settings

    settings = load_settings(SECTIONS)
    rows, cpu0 = [], time.process_time()
    for scene in args.scene:
        for seed in args.seeds:
            rows += scene_rows(scene, seed, settings)
    result = {"rows": rows, "colour": confusion(rows, "colour"), "shape": confusion(rows, "shape"),
              "cpu_s": time.process_time() - cpu0}
    print(f"{len(rows)} objects, scenes {args.scene} seeds {args.seeds}, CPU {result['cpu_s']:.0f} s")
    print("colour (true: perceived counts)\n" + _table(result["colour"]))
    print("shape (true: perceived counts)\n" + _table(result["shape"]))
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(result, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
