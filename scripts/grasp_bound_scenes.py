"""Label the objects of many settled clutter scenes with their geometric bound (evaluation only).

    PYTHONPATH=python python scripts/grasp_bound_scenes.py --protocol pile \
        --objects /work/shared/objects/vgn_packed_train --seeds 0 200 --json out.json

Each scene is built by the product's scene builders (``make_scene``: a pile is dropped and settled
there), loaded into the simulator without a camera and left to settle for the rough view's time
(``scan.rough_view_s``), as a ``bench clutter`` round does before it labels its objects; no robot
motion. Prints the share of objects graspable under each bound, with the table rule and by widths
alone (:mod:`grasp_pipeline.evaluation.grasp_bound`).
"""

from __future__ import annotations

import argparse
import json
import time

from grasp_pipeline.app.sim_system import make_scene
from grasp_pipeline.bench.clutter_round import clutter_settings
from grasp_pipeline.evaluation.grasp_bound import CLASSES, LABELS, bounds_of_spec, bounds_of_world
from grasp_pipeline.sim.world import SimWorld


def _scene_rows(protocol: str, seed: int, objects: str, settings) -> list[dict]:
    spec = make_scene(protocol, seed, settings, objects)
    at_spec = bounds_of_spec(spec, settings.grasp_bound)
    world = SimWorld(spec, settings.sim, settings.camera, camera=False)
    try:
        world.step(int(round(settings.scan.rough_view_s / world.timestep_s)))
        settled = bounds_of_world(world, settings.grasp_bound)
    finally:
        world.close()
    return [{"seed": seed, "name": name, **b.to_dict(), "label_before_settling": at_spec[name].label}
            for name, b in settled.items()]


def _shares(rows: list[dict], key: str) -> dict:
    n = len(rows)
    return {c: round(sum(r[key] in LABELS[: i + 1] for r in rows) / n, 4) for i, c in enumerate(CLASSES)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--protocol", choices=("pile", "packed"), required=True)
    ap.add_argument("--objects", required=True)
    ap.add_argument("--seeds", type=int, nargs=2, default=(0, 200), metavar=("FIRST", "END"))
    ap.add_argument("--json", default=None)
    args = ap.parse_args()
    settings = clutter_settings()
    rows, t0, label_s = [], time.perf_counter(), 0.0
    for seed in range(*args.seeds):
        rows += _scene_rows(args.protocol, seed, args.objects, settings)
    out = {"protocol": args.protocol, "objects": args.objects, "seeds": list(args.seeds), "n_objects": len(rows),
           "graspable": _shares(rows, "label"), "graspable_width_only": _shares(rows, "label_width_only"),
           "graspable_before_settling": _shares(rows, "label_before_settling"),
           "wall_s": round(time.perf_counter() - t0, 1), "rows": rows}
    print(json.dumps({k: v for k, v in out.items() if k != "rows"}, indent=1))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
