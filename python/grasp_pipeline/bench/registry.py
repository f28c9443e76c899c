"""The benchmarks of ``grasp-pipeline bench``: one :class:`Benchmark` each — its name, its
arguments (:mod:`.arguments`), its entry point on the parsed arguments (returning its typed
result) and what the command prints. :mod:`grasp_pipeline.cli` builds the ``bench``
sub-commands from :data:`BENCHMARKS`: adding a benchmark is its entry there (with its
arguments function and the call of its entry point); the command line needs no change.

An entry point's module is imported only when its benchmark runs (building the command line
imports none of them)."""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from typing import Any, Callable, Optional

from . import arguments


def print_json(result: Any, args: argparse.Namespace) -> int:
    """Print the result's JSON (sorted keys); exit code 0."""
    from ..report.serialize import dumps

    print(dumps(result, sort_keys=True))
    return 0


@dataclass(frozen=True)
class Benchmark:
    """One ``grasp-pipeline bench <name>``: ``add_arguments(parser)`` fills its parser,
    ``run(args)`` runs it and returns its typed result, ``report(result, args)`` prints what
    the command prints and returns its exit code; ``uses_mujoco``: the command chooses the GL
    backend first."""

    name: str
    help: str
    add_arguments: Callable[[argparse.ArgumentParser], None]
    run: Callable[[argparse.Namespace], Any]
    report: Callable[[Any, argparse.Namespace], int] = print_json
    description: Optional[str] = None
    uses_mujoco: bool = True


def _overrides(args: argparse.Namespace) -> tuple:
    return args.config, args.sets


def _print_headline(text: str, result: Any, args: argparse.Namespace) -> int:
    """The headline, where the files are; exit code 1 when nothing ran to its end (``failed``)."""
    print(text)
    print(f"JSON: {args.json}\nsummary: {result.summary}")
    return 1 if result.status == "failed" else 0


def _perception(args: argparse.Namespace):
    from .perception_bench import run_perception_benchmark

    return run_perception_benchmark(frames=args.frames, json_path=args.json,
                                    baseline_frames=0 if args.no_baseline else args.baseline_frames)


def _sim(args: argparse.Namespace):
    from .sim_bench import run_sim_benchmark

    return run_sim_benchmark(seconds=args.seconds, json_path=args.json,
                             pick_scene=None if args.pick_scene == "none" else args.pick_scene,
                             pick_seed=args.pick_seed, pick_objects=args.pick_objects,
                             overrides=_overrides(args))


def _planning(args: argparse.Namespace):
    from .planning_bench import run_planning_benchmark

    return run_planning_benchmark(scenes=args.scenes, seed=args.seed, json_path=args.json,
                                  overrides=_overrides(args), hard_pairs=args.hard, hard_only=args.hard_only)


def _grasp(args: argparse.Namespace):
    from .grasp_bench import run_grasp_benchmark

    return run_grasp_benchmark(scenes=args.scenes, seed=args.seed, workers=args.workers, json_path=args.json,
                               out_dir=args.out, progress=not args.no_progress,
                               scene_timeout_s=args.scene_timeout, overrides=_overrides(args),
                               backend=args.backend, address=args.address,
                               jobs_per_worker=args.jobs_per_worker)


def _report_grasp(result: Any, args: argparse.Namespace) -> int:
    from .grasp_bench import headline

    return _print_headline(headline(result), result, args)


def _workers(args: argparse.Namespace):
    from .workers_bench import run_workers_benchmark

    return run_workers_benchmark(scenes=args.scenes, seed=args.seed, workers=args.workers, json_path=args.json,
                                 out_dir=args.out, progress=not args.no_progress, overrides=_overrides(args))


def _frames(args: argparse.Namespace):
    from .frames_bench import run_frames_benchmark

    return run_frames_benchmark(scenes=args.scenes, seed=args.seed, workers=args.workers, json_path=args.json,
                                out_dir=args.out, progress=not args.no_progress, overrides=_overrides(args))


def _clutter(args: argparse.Namespace):
    from .clutter_bench import run_clutter_benchmark

    return run_clutter_benchmark(protocol=args.protocol, objects=args.objects, rounds=args.rounds,
                                 seeds=args.seed, workers=args.workers, json_path=args.json,
                                 out_dir=args.out, progress=not args.no_progress,
                                 round_timeout_s=args.round_timeout, overrides=_overrides(args),
                                 backend=args.backend, address=args.address, rerun_dir=args.rerun,
                                 jobs_per_worker=args.jobs_per_worker)


def _report_clutter(result: Any, args: argparse.Namespace) -> int:
    from .clutter_bench import headline

    return _print_headline(headline(result), result, args)


def _language(args: argparse.Namespace):
    from .language_bench import run_language_benchmark

    return run_language_benchmark(scenes=args.scene, seeds=args.seeds, json_path=args.json,
                                  overrides=_overrides(args))


def _report_language(result: Any, args: argparse.Namespace) -> int:
    from .language_bench import summary_text

    print(summary_text(result, args.scene, args.seeds))
    return 0


#: name -> benchmark, in the order ``grasp-pipeline bench --help`` lists them.
BENCHMARKS: dict[str, Benchmark] = {b.name: b for b in (
    Benchmark("perception", "per-frame perception speed vs the Python baseline",
              arguments.perception, _perception, uses_mujoco=False),
    Benchmark("sim", "simulation real-time factors and the pick loop's CPU breakdown", arguments.sim, _sim),
    Benchmark("planning", "planning success / speed on random scenes", arguments.planning, _planning),
    Benchmark(
        "grasp", "the whole product on random scenes: pick success, accuracy, time", arguments.grasp,
        _grasp, _report_grasp,
        description="Rough view, scan and pick every object into the tray on N seeded random "
                    "scenes (1-6 objects), scored against ground truth; scenes run in W spawned "
                    "worker processes. Writes the JSON, OUT/summary.md and PNG plots."),
    Benchmark(
        "workers", "worker scaling: the same grasp-benchmark scenes with 1 and with W workers",
        arguments.workers, _workers,
        description="Runs 'bench grasp' twice on the same seeded scenes (1 worker, then W) and "
                    "prints the wall-time speed-up and whether both runs gave the same results."),
    Benchmark(
        "frames", "frames on demand vs continuous frames: throughput and per-object outcomes",
        arguments.frames, _frames,
        description="Runs 'bench grasp' twice on the same seeded scenes (camera.frames=continuous, "
                    "the old path, then on_demand) and prints both throughputs, the speed-up and "
                    "every object whose outcome (picked, failed stage and reason) differs."),
    Benchmark(
        "clutter", "cluttered tables (VGN/GIGA packed and pile protocols): GSR, declutter rate",
        arguments.clutter, _clutter, _report_clutter,
        description="Rounds of the VGN/GIGA clutter benchmark with the whole product: build the "
                    "scene, rough view, scan, then pick one object at a time into the tray, looking "
                    "again after each attempt; a round ends when the table is clear, nothing graspable "
                    "is proposed, or after 2 failed attempts in a row. Reports grasp success rate "
                    "(successes / attempts) and declutter rate (successes / objects placed) per seed "
                    "and mean +- std, failures by stage, success by object, segmentation quality at the "
                    "scan, and times; writes the JSON, OUT/summary.md, plots and a PNG per failed attempt."),
    Benchmark(
        "language", "colour and shape words of the perceived objects vs the truth",
        arguments.language, _language, _report_language,
        description="Builds each scene, takes the rough view and the active scan as run does, names "
                    "every perceived object (colour and shape words; no ground truth) and compares "
                    "with the true objects' words; prints the confusion of the words and writes the "
                    "rows (--json). A measurement of the language words, not a test."),
)}
