"""Instruction counts of the per-frame perception path (a repeatable figure on a busy machine).

Saves the benchmark's four synthetic frames once (natively), then runs a few frames through
``_core.Perception.process`` so that callgrind can count the instructions inside the call:

    PYTHONPATH=python .venv/bin/python scripts/perception_callgrind.py save /tmp/perception_frames.npz
    PYTHONPATH=python valgrind --tool=callgrind --collect-atstart=no \\
        --toggle-collect='grasp_core::Perception::process*' --callgrind-out-file=/tmp/cg.out \\
        .venv/bin/python scripts/perception_callgrind.py run /tmp/perception_frames.npz
    callgrind_annotate --inclusive=yes /tmp/cg.out | grep grasp_core::

"Collected" / FRAMES = instructions per frame.
"""

from __future__ import annotations

import argparse

import numpy as np

DISTINCT_FRAMES = 4  # as bench perception
FRAMES = 8           # frames run under callgrind (each of the four twice)


def save(path: str) -> None:
    """Render the benchmark's frames and store points + camera positions in an npz."""
    from grasp_pipeline.perception.synthetic import tabletop_frame

    frames = [tabletop_frame(seed=s) for s in range(DISTINCT_FRAMES)]
    np.savez(path, **{f"p{i}": f[0] for i, f in enumerate(frames)},
             **{f"c{i}": f[1][:3, 3] for i, f in enumerate(frames)})


def run(path: str) -> None:
    """FRAMES frames through one Perception session (30 Hz capture times)."""
    from grasp_pipeline import _core

    d = np.load(path)
    per = _core.Perception(_core.SceneFilterParams(), _core.ObbParams())
    for i in range(FRAMES):
        k = i % DISTINCT_FRAMES
        out = per.process(d[f"p{k}"], d[f"c{k}"], i / 30.0)
    print(f"{FRAMES} frames, {len(out.estimates)} estimates in the last")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("mode", choices=("save", "run"))
    ap.add_argument("path")
    args = ap.parse_args()
    (save if args.mode == "save" else run)(args.path)


if __name__ == "__main__":
    main()
