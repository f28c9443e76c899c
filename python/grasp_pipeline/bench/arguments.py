"""The command-line arguments of each benchmark (``grasp-pipeline bench <name> ...``), as
:mod:`.registry` names them: one function per benchmark, filling its argparse parser. Only
argparse here: building the command line imports no benchmark."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..cli_options import (add_backend_options, add_config_options, non_negative_int, positive_float,
                           positive_int)

#: The parameter sets a simulated run reads (for --config/--set help).
RUN_SECTIONS = "scene_filter, obb, camera, sim, motion, scan, grasp"
ONE_TO_THREE_OBJECTS = "sim.object_count=[1,3]"


def perception(p: argparse.ArgumentParser) -> None:
    p.add_argument("--frames", type=positive_int, default=50, help="frames to time (default 50)")
    p.add_argument("--json", type=Path, required=True, help="where to write the JSON result")
    p.add_argument("--baseline-frames", type=non_negative_int, default=5,
                   help="frames for the slow Python/Open3D baseline (default 5)")
    p.add_argument("--no-baseline", action="store_true",
                   help="skip the baseline (then no speedup is reported)")


def sim(p: argparse.ArgumentParser) -> None:
    p.add_argument("--seconds", type=positive_float, default=5.0, help="simulated seconds")
    p.add_argument("--json", type=Path, required=True)
    p.add_argument("--pick-scene", default="packed", choices=["packed", "pile", "random", "sparse", "reference", "none"],
                   help="scene of the pick-loop round (run --declutter; default packed; none: no round)")
    p.add_argument("--pick-seed", type=non_negative_int, default=3, help="seed of the pick-loop scene (default 3)")
    p.add_argument("--pick-objects", default="builtin", metavar="builtin|DIR",
                   help="object set of a packed/pile pick-loop scene (default builtin)")
    add_config_options(p, "scene_filter, obb, camera, sim, clutter, motion, scan, grasp", ONE_TO_THREE_OBJECTS)


def planning(p: argparse.ArgumentParser) -> None:
    p.add_argument("--scenes", type=positive_int, default=50)
    p.add_argument("--seed", type=non_negative_int, default=0)
    p.add_argument("--json", type=Path, required=True)
    p.add_argument("--hard", type=non_negative_int, default=0, metavar="N",
                   help="also: checker throughput and N blocked-line start/goal pairs per perceived "
                        "packed scene (seeds as --seed/--scenes)")
    p.add_argument("--hard-only", action="store_true", help="with --hard: skip the executed motions")
    add_config_options(p, RUN_SECTIONS, ONE_TO_THREE_OBJECTS)


def _scene_benchmark(p: argparse.ArgumentParser, scenes: int, workers: int, workers_help: str,
                     out: str, out_help: str) -> None:
    """``--scenes --seed --workers --json --out --no-progress`` of the scene benchmarks."""
    p.add_argument("--scenes", type=positive_int, default=scenes, help=f"number of random scenes (default {scenes})")
    p.add_argument("--seed", type=non_negative_int, default=0, help="benchmark seed; scene seeds derive from it")
    p.add_argument("--workers", type=positive_int, default=workers, help=workers_help)
    p.add_argument("--json", type=Path, required=True, help="where to write the JSON result")
    p.add_argument("--out", type=Path, default=Path(out), help=out_help)
    p.add_argument("--no-progress", action="store_true", help="no progress bar")


def _jobs_per_worker(p: argparse.ArgumentParser) -> None:
    """``--jobs-per-worker`` of the benchmarks that run simulated jobs on local workers."""
    from .jobs import SIM_JOBS_PER_WORKER

    p.add_argument("--jobs-per-worker", type=positive_int, default=SIM_JOBS_PER_WORKER, metavar="N",
                   help=f"jobs a local worker process runs one after the other, each as in a fresh "
                        f"process (default {SIM_JOBS_PER_WORKER}; 1: a new process per job)")


def grasp(p: argparse.ArgumentParser) -> None:
    _scene_benchmark(p, scenes=100, workers=1, workers_help="worker processes (one thread each)",
                     out="out/bench_grasp", out_help="folder for summary.md, plots and per-scene reports")
    p.add_argument("--scene-timeout", type=positive_float, default=1800.0, metavar="S",
                   help="wall-clock limit of one scene in seconds (default 1800)")
    add_backend_options(p)
    _jobs_per_worker(p)
    add_config_options(p, RUN_SECTIONS, ONE_TO_THREE_OBJECTS)


def workers(p: argparse.ArgumentParser) -> None:
    _scene_benchmark(p, scenes=6, workers=2, workers_help="workers of the second run (default 2)",
                     out="out/bench_workers", out_help="folder for both runs' JSON, summaries and plots")
    add_config_options(p, RUN_SECTIONS, ONE_TO_THREE_OBJECTS)


def frames(p: argparse.ArgumentParser) -> None:
    _scene_benchmark(p, scenes=6, workers=2, workers_help="worker processes of both runs",
                     out="out/bench_frames", out_help="folder for both runs' JSON, summaries and plots")
    add_config_options(p, RUN_SECTIONS, ONE_TO_THREE_OBJECTS)


def clutter(p: argparse.ArgumentParser) -> None:
    p.add_argument("--protocol", choices=["packed", "pile", "sparse"], default="packed",
                   help="scene protocol (default packed)")
    p.add_argument("--objects", default="builtin", metavar="builtin|DIR",
                   help="object set: the built-in set or a folder of URDF (VGN layout) / OBJ / STL objects")
    p.add_argument("--rounds", type=positive_int, default=20, help="rounds per seed (default 20)")
    p.add_argument("--seed", type=non_negative_int, nargs="+", default=[0],
                   help="benchmark seed(s); each seed runs --rounds rounds (round seeds derive from it)")
    p.add_argument("--workers", type=positive_int, default=1, help="worker processes (one thread each)")
    p.add_argument("--json", type=Path, required=True, help="where to write the JSON result")
    p.add_argument("--out", type=Path, default=Path("out/bench_clutter"),
                   help="folder for summary.md, plots, failure PNGs and per-round reports")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--round-timeout", type=positive_float, default=3600.0, metavar="S",
                   help="wall-clock limit of one round in seconds (default 3600)")
    p.add_argument("--rerun", type=Path, default=None, metavar="DIR",
                   help="also write one Rerun recording per round into this folder, named like the "
                        "round's folder: DIR/seed_<K>_round_<NNN>_scene_<S>.rrd (open one with "
                        "'rerun FILE.rrd'). Needs pip install 'grasp-pipeline[rerun]'")
    add_backend_options(p)
    _jobs_per_worker(p)
    add_config_options(p, "scene_filter, obb, camera, sim, clutter, motion, scan, grasp, declutter, "
                       "grasp_bound", "clutter.objects_per_scene=3")


def language(p: argparse.ArgumentParser) -> None:
    scenes = ("packed", "pile", "sparse", "random", "reference")
    p.add_argument("--scene", nargs="+", choices=scenes, default=["packed"], metavar="SCENE",
                   help=f"scene(s), each with every seed: {', '.join(scenes)} (default packed)")
    p.add_argument("--seeds", nargs="+", type=non_negative_int, default=[0],
                   help="scene seed(s) (default 0)")
    p.add_argument("--json", type=Path, default=None, help="also write the JSON result here")
    add_config_options(p, RUN_SECTIONS + ", language", ONE_TO_THREE_OBJECTS)
