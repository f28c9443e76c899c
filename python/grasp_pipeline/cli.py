"""The ``grasp-pipeline`` command line.

Sub-commands:
  demo                      the default headless demo: ``run`` on the reference scene
  run                       rough view, active scan, pick (and place) the selected objects
  bench perception|sim|planning|grasp|workers|frames
                            benchmarks that print figures and write JSON
  record                    the reference policy's episodes as a LeRobot dataset
  eval --policy DIR         a policy's success in the environment (closed loop, seeded scenes)
  train                     a small LeRobot policy (ACT) trained on a ``record`` dataset
  perceive FILE             one point cloud from disk (.pcd/.ply/.npy) through the
                            scene filter and estimates; prints, writes JSON (+ PNG)

Every sub-command accepts ``--log-level``. Each sub-command's work lives in its
own module; this file only parses arguments and dispatches.
"""

from __future__ import annotations

import argparse
import logging
import sys
from pathlib import Path
from typing import Optional

from .exceptions import GraspPipelineError
from .messages import shorten

log = logging.getLogger("grasp_pipeline")


def _add_bench(sub: argparse._SubParsersAction) -> None:
    bench = sub.add_parser("bench", help="benchmarks (print figures, write JSON)")
    bsub = bench.add_subparsers(dest="bench", required=True)

    p = bsub.add_parser("perception", help="per-frame perception speed vs the Python baseline")
    p.add_argument("--frames", type=positive_int, default=50, help="frames to time (default 50)")
    p.add_argument("--json", type=Path, required=True, help="where to write the JSON result")
    p.add_argument("--baseline-frames", type=non_negative_int, default=5,
                   help="frames for the slow Python/Open3D baseline (default 5)")
    p.add_argument("--no-baseline", action="store_true",
                   help="skip the baseline (then no speedup is reported)")

    s = bsub.add_parser("sim", help="simulation real-time factors and the pick loop's CPU breakdown")
    s.add_argument("--seconds", type=positive_float, default=5.0, help="simulated seconds")
    s.add_argument("--json", type=Path, required=True)
    s.add_argument("--pick-scene", default="packed", choices=["packed", "pile", "random", "sparse", "reference", "none"],
                   help="scene of the pick-loop round (run --declutter; default packed; none: no round)")
    s.add_argument("--pick-seed", type=non_negative_int, default=3, help="seed of the pick-loop scene (default 3)")
    s.add_argument("--pick-objects", default="builtin", metavar="builtin|DIR",
                   help="object set of a packed/pile pick-loop scene (default builtin)")
    _add_config_options(s, "scene_filter, obb, camera, sim, clutter, motion, scan, grasp", "sim.object_count=[1,3]")

    pl = bsub.add_parser("planning", help="planning success / speed on random scenes")
    pl.add_argument("--scenes", type=positive_int, default=50)
    pl.add_argument("--seed", type=non_negative_int, default=0)
    pl.add_argument("--json", type=Path, required=True)
    pl.add_argument("--hard", type=non_negative_int, default=0, metavar="N",
                    help="also: checker throughput and N blocked-line start/goal pairs per perceived "
                         "packed scene (seeds as --seed/--scenes)")
    pl.add_argument("--hard-only", action="store_true", help="with --hard: skip the executed motions")
    _add_config_options(pl, "scene_filter, obb, camera, sim, motion, scan, grasp", "sim.object_count=[1,3]")

    g = bsub.add_parser(
        "grasp", help="the whole product on random scenes: pick success, accuracy, time",
        description="Rough view, scan and pick every object into the tray on N seeded random "
                    "scenes (1-6 objects), scored against ground truth; scenes run in W spawned "
                    "worker processes. Writes the JSON, OUT/summary.md and PNG plots.")
    _add_scene_benchmark_options(g, scenes=100, workers=1, workers_help="worker processes (one thread each)",
                                 out="out/bench_grasp", out_help="folder for summary.md, plots and per-scene reports")
    g.add_argument("--scene-timeout", type=positive_float, default=1800.0, metavar="S",
                   help="wall-clock limit of one scene in seconds (default 1800)")
    _add_backend_options(g)
    _add_config_options(g, "scene_filter, obb, camera, sim, motion, scan, grasp", "sim.object_count=[1,3]")

    w = bsub.add_parser(
        "workers", help="worker scaling: the same grasp-benchmark scenes with 1 and with W workers",
        description="Runs 'bench grasp' twice on the same seeded scenes (1 worker, then W) and "
                    "prints the wall-time speed-up and whether both runs gave the same results.")
    _add_scene_benchmark_options(w, scenes=6, workers=2, workers_help="workers of the second run (default 2)",
                                 out="out/bench_workers", out_help="folder for both runs' JSON, summaries and plots")
    _add_config_options(w, "scene_filter, obb, camera, sim, motion, scan, grasp", "sim.object_count=[1,3]")
    f = bsub.add_parser(
        "frames", help="frames on demand vs continuous frames: throughput and per-object outcomes",
        description="Runs 'bench grasp' twice on the same seeded scenes (camera.frames=continuous, "
                    "the old path, then on_demand) and prints both throughputs, the speed-up and "
                    "every object whose outcome (picked, failed stage and reason) differs.")
    _add_scene_benchmark_options(f, scenes=6, workers=2, workers_help="worker processes of both runs",
                                 out="out/bench_frames", out_help="folder for both runs' JSON, summaries and plots")
    _add_config_options(f, "scene_filter, obb, camera, sim, motion, scan, grasp", "sim.object_count=[1,3]")
    _add_clutter_bench(bsub)


def _add_clutter_bench(bsub) -> None:
    c = bsub.add_parser(
        "clutter", help="cluttered tables (VGN/GIGA packed and pile protocols): GSR, declutter rate",
        description="Rounds of the VGN/GIGA clutter benchmark with the whole product: build the "
                    "scene, rough view, scan, then pick one object at a time into the tray, looking "
                    "again after each attempt; a round ends when the table is clear, nothing graspable "
                    "is proposed, or after 2 failed attempts in a row. Reports grasp success rate "
                    "(successes / attempts) and declutter rate (successes / objects placed) per seed "
                    "and mean +- std, failures by stage, success by object, segmentation quality at the "
                    "scan, and times; writes the JSON, OUT/summary.md, plots and a PNG per failed attempt.")
    c.add_argument("--protocol", choices=["packed", "pile", "sparse"], default="packed",
                   help="scene protocol (default packed)")
    c.add_argument("--objects", default="builtin", metavar="builtin|DIR",
                   help="object set: the built-in set or a folder of URDF (VGN layout) / OBJ / STL objects")
    c.add_argument("--rounds", type=positive_int, default=20, help="rounds per seed (default 20)")
    c.add_argument("--seed", type=non_negative_int, nargs="+", default=[0],
                   help="benchmark seed(s); each seed runs --rounds rounds (round seeds derive from it)")
    c.add_argument("--workers", type=positive_int, default=1, help="worker processes (one thread each)")
    c.add_argument("--json", type=Path, required=True, help="where to write the JSON result")
    c.add_argument("--out", type=Path, default=Path("out/bench_clutter"),
                   help="folder for summary.md, plots, failure PNGs and per-round reports")
    c.add_argument("--no-progress", action="store_true", help="no progress bar")
    c.add_argument("--round-timeout", type=positive_float, default=3600.0, metavar="S",
                   help="wall-clock limit of one round in seconds (default 3600)")
    c.add_argument("--rerun", type=Path, default=None, metavar="DIR",
                   help="also write one Rerun recording per round into this folder, named like the "
                        "round's folder: DIR/seed_<K>_round_<NNN>_scene_<S>.rrd (open one with "
                        "'rerun FILE.rrd'). Needs pip install 'grasp-pipeline[rerun]'")
    _add_backend_options(c)
    _add_config_options(c, "scene_filter, obb, camera, sim, clutter, motion, scan, grasp, declutter, "
                        "grasp_bound", "clutter.objects_per_scene=3")


def _add_record(sub: argparse._SubParsersAction) -> None:
    r = sub.add_parser(
        "record", help="the reference policy's episodes as a LeRobot dataset (one episode per task)",
        description="Episodes of the environment grasp_pipeline/PickPlace-v0 (one task on one seeded "
                    "scene each) played by the reference policy (the pipeline acting through the "
                    "environment's actions), recorded as a LeRobot dataset (format v3.0): wrist and "
                    "scene camera RGB, joint state, end-effector pose, joint-target and "
                    "end-effector-delta actions at --fps, the task and the outcome per episode. "
                    "Needs the 'dataset' extra (pip install 'grasp-pipeline[dataset]').")
    r.add_argument("--protocol", choices=["sparse", "packed", "pile"], default="sparse",
                   help="scene protocol (default sparse)")
    r.add_argument("--objects", default="builtin", metavar="builtin|DIR",
                   help="object set of packed/pile scenes: the built-in set or a folder of URDF/OBJ/STL objects")
    r.add_argument("--episodes", type=positive_int, required=True, help="episodes to write")
    r.add_argument("--seed", type=non_negative_int, default=0, help="seed; the scene seeds derive from it")
    r.add_argument("--workers", type=positive_int, default=1, help="worker processes (one thread each)")
    r.add_argument("--out", type=Path, required=True, help="the dataset folder (new or empty)")
    r.add_argument("--fps", type=positive_int, default=None, help="recording rate in simulated time "
                   "(default record.yaml: 15)")
    r.add_argument("--image-size", type=positive_int, default=None, metavar="PX",
                   help="square image side (default record.yaml: 256)")
    r.add_argument("--depth", action="store_true", help="also depth images of both cameras")
    r.add_argument("--keep-failed", action="store_true",
                   help="keep failed episodes too (marked episode.success = false)")
    r.add_argument("--no-progress", action="store_true", help="no progress bar")
    r.add_argument("--job-timeout", type=positive_float, default=3600.0, metavar="S",
                   help="wall-clock limit of one worker job (env.yaml episodes_per_job episodes) in "
                        "seconds (default 3600)")
    r.add_argument("--rerun", type=Path, default=None, metavar="DIR",
                   help="also a Rerun recording of every episode: DIR/episode_<i>_scene_<seed>.rrd "
                        "(open with 'rerun FILE.rrd'). Needs pip install 'grasp-pipeline[rerun]'")
    _add_backend_options(r)
    _add_config_options(r, "record, env, scene_filter, obb, camera, sim, clutter, motion, scan, grasp",
                        "record.scene_azimuth_deg=90")


def _add_recording_options(p: argparse.ArgumentParser) -> None:
    """``--image-size --fps --depth``: the observations, as ``record`` recorded them."""
    p.add_argument("--image-size", type=positive_int, default=None, metavar="PX",
                   help="square camera image side, as the dataset was recorded (default record.yaml: 256)")
    p.add_argument("--fps", type=positive_int, default=None,
                   help="control rate, as the dataset was recorded (default record.yaml: 15)")


def _add_eval(sub: argparse._SubParsersAction) -> None:
    e = sub.add_parser(
        "eval", help="a policy's success rate in the environment (closed loop, seeded scenes)",
        description="Runs a policy saved by LeRobot (save_pretrained, with its processors) or the "
                    "reference policy (the pipeline through the environment's actions) for N episodes "
                    "of grasp_pipeline/PickPlace-v0 on seeded scenes; writes eval.json (success rate "
                    "with a 95%% interval, per task word and per object, failure reasons, steps and "
                    "seconds per episode), summary.md and a video per episode.")
    e.add_argument("--policy", required=True, metavar="DIR|reference",
                   help="a LeRobot policy folder, or 'reference'")
    e.add_argument("--protocol", choices=["sparse", "packed", "pile"], default="sparse",
                   help="scene protocol (default sparse)")
    e.add_argument("--objects", default="builtin", metavar="builtin|DIR",
                   help="object set of packed/pile scenes")
    e.add_argument("--episodes", type=positive_int, default=10, help="episodes (default 10)")
    e.add_argument("--seed", type=non_negative_int, default=1000,
                   help="seed; the scene seeds derive from it as record's (default 1000: not record's 0)")
    e.add_argument("--workers", type=positive_int, default=1, help="worker processes (one thread each)")
    e.add_argument("--max-steps", type=positive_int, default=None,
                   help="steps per episode before it is truncated (default env.yaml time_limit_s x fps)")
    e.add_argument("--device", choices=["cpu", "cuda"], default="cpu", help="where the policy runs")
    e.add_argument("--out", type=Path, required=True, help="the report folder (new or empty)")
    e.add_argument("--no-video", action="store_true", help="no video per episode")
    e.add_argument("--depth", action="store_true", help="the environment also gives depth images")
    e.add_argument("--no-progress", action="store_true", help="no progress bar")
    e.add_argument("--job-timeout", type=positive_float, default=3600.0, metavar="S",
                   help="wall-clock limit of one worker job in seconds (default 3600)")
    _add_recording_options(e)
    _add_backend_options(e)
    _add_config_options(e, "env, record, scene_filter, obb, camera, sim, clutter, motion, scan, grasp",
                        "env.time_limit_s=30")


def _add_train(sub: argparse._SubParsersAction) -> None:
    t = sub.add_parser(
        "train", help="a small LeRobot policy (ACT, from scratch) trained on a record dataset",
        description="Trains LeRobot's ACT (no pretrained backbone download) on a record dataset's "
                    "successful episodes and saves it with save_pretrained (policy and processors) "
                    "for eval --policy. Sizes and optimiser: config/train.yaml.")
    t.add_argument("--dataset", type=Path, required=True, help="a dataset written by grasp-pipeline record")
    t.add_argument("--out", type=Path, required=True, help="the policy folder (new or empty)")
    t.add_argument("--steps", type=positive_int, default=None, help="optimisation steps (default train.yaml)")
    t.add_argument("--batch-size", type=positive_int, default=None, help="frames per step (default train.yaml)")
    t.add_argument("--seed", type=non_negative_int, default=0, help="seed of the initialisation and sampling")
    t.add_argument("--device", choices=["cpu", "cuda"], default="cpu", help="where to train")
    _add_recording_options(t)
    _add_config_options(t, "train, record", "train.dim_model=256")


def _add_backend_options(p: argparse.ArgumentParser) -> None:
    """``--backend local|ray`` and ``--address`` of the benchmarks that fan out."""
    p.add_argument("--backend", choices=["local", "ray"], default="local",
                   help="local: spawned processes on this machine; ray: Ray tasks (pip install "
                        "'grasp_pipeline[ray]'), a local Ray instance with --workers CPUs unless "
                        "--address joins a cluster")
    p.add_argument("--address", default=None, metavar="HOST:PORT",
                   help="with --backend ray: the Ray cluster to join (e.g. 10.0.0.5:6379)")


def _add_scene_benchmark_options(p: argparse.ArgumentParser, scenes: int, workers: int, workers_help: str,
                                 out: str, out_help: str) -> None:
    """``--scenes --seed --workers --json --out --no-progress`` of the scene benchmarks."""
    p.add_argument("--scenes", type=positive_int, default=scenes, help=f"number of random scenes (default {scenes})")
    p.add_argument("--seed", type=non_negative_int, default=0, help="benchmark seed; scene seeds derive from it")
    p.add_argument("--workers", type=positive_int, default=workers, help=workers_help)
    p.add_argument("--json", type=Path, required=True, help="where to write the JSON result")
    p.add_argument("--out", type=Path, default=Path(out), help=out_help)
    p.add_argument("--no-progress", action="store_true", help="no progress bar")


def _add_config_options(p: argparse.ArgumentParser, sections: str, example: str) -> None:
    """``--config FILE`` and repeatable ``--set name=value`` (see grasp_pipeline.settings)."""
    p.add_argument("--config", default=None, metavar="FILE",
                   help=f"YAML with one section per parameter set ({sections}) overriding the defaults")
    p.add_argument("--set", dest="sets", action="append", default=[], metavar="NAME=VALUE",
                   help=f"override one parameter (repeatable), e.g. --set {example}")


def _add_perceive(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "perceive", help="table plane + object estimates of one point-cloud file",
        description="Run the scene filter and the object estimates on one point cloud from "
                    "disk (.pcd, .ply or .npy; coordinates in metres). Say where the world "
                    "frame (z up) is with --T-world-camera or --up. Example: grasp-pipeline "
                    "perceive scan.pcd --up 0 -0.64 -0.77 --json out.json --png out.png")
    p.add_argument("file", type=Path, help="point cloud: .pcd (any encoding), .ply, .npy "
                   "((N,3) or organized (H,W,3))")
    frame = p.add_mutually_exclusive_group(required=True)
    frame.add_argument("--T-world-camera", dest="T_world_camera", nargs="+", metavar="V",
                       help="16 numbers (or one comma-separated string), row-major 4x4 rigid "
                            "transform mapping the cloud's frame into world (z up); write FILE "
                            "before this option")
    frame.add_argument("--up", nargs=3, type=float, metavar=("X", "Y", "Z"),
                       help="world up (+z) as a vector in the cloud's frame; the world origin "
                            "is then the cloud's origin (the camera)")
    p.add_argument("--json", type=Path, required=True, help="where to write the JSON report")
    p.add_argument("--png", type=Path, default=None, help="also write an RViz-like PNG snapshot")
    p.add_argument("--max-range-m", dest="max_range_m", type=float, default=None, metavar="M",
                   help="workspace: drop points farther than M metres from the camera "
                        "(workspace.workspace_max_range_m; e.g. 1.5)")
    p.add_argument("--crop", nargs=6, type=float, default=None,
                   metavar=("XMIN", "XMAX", "YMIN", "YMAX", "ZMIN", "ZMAX"),
                   help="workspace: drop points outside this box in world coordinates [m] "
                        "(workspace.workspace_crop_box_m)")
    _add_config_options(p, "scene_filter / obb / workspace", "cluster_eps=0.02")


def _checked(convert, ok, expected: str):
    """An argparse type: ``convert(text)`` that must satisfy ``ok``, else a message."""
    def parse(text: str):
        try:
            v = convert(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {expected}, got {text!r}") from None
        if not ok(v):
            raise argparse.ArgumentTypeError(f"expected {expected}, got {text}")
        return v

    parse.__name__ = expected
    return parse


#: argparse types: whole numbers >= 1 / >= 0, numbers > 0 / finite (NaN and inf refused).
positive_int = _checked(int, lambda v: v >= 1, "a whole number >= 1")
non_negative_int = _checked(int, lambda v: v >= 0, "a whole number >= 0")
positive_float = _checked(float, lambda v: 0 < v < float("inf"), "a finite number > 0")
finite_float = _checked(float, lambda v: abs(v) < float("inf"), "a finite number")


def _add_pick_options(p: argparse.ArgumentParser, out: str) -> None:
    """Options shared by ``run`` and ``demo``."""
    p.add_argument("--select", nargs="+", type=finite_float, metavar="X Y", default=None,
                   help="world (x, y) of the objects to pick, as pairs: --select 0.56 -0.03 0.52 0.09")
    p.add_argument("--out", type=Path, default=Path(out), help=f"folder for images and video (default {out})")
    p.add_argument("--json", type=Path, default=None, help="report path (default OUT/report.json)")
    p.add_argument("--no-video", action="store_true", help="skip the MP4")
    p.add_argument("--no-scan", action="store_true", help="pick from the rough (oblique) view")
    p.add_argument("--rerun", type=Path, default=None, metavar="PATH.rrd",
                   help="also write a Rerun recording of the run (3-D point cloud, boxes, grasps, "
                        "camera, TCP paths, stages, series on simulated time); open it with "
                        "'rerun PATH.rrd'. Needs pip install 'grasp-pipeline[rerun]'")
    _add_config_options(p, "scene_filter, obb, camera, sim, clutter, motion, scan, grasp, video, "
                        "language, rerun",
                        "grasp.lift_height_m=0.12")


def _add_run(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "run", help="scan the table, then pick the selected objects into the tray",
        description="Headless run in MuJoCo: rough view from the start pose, active scan "
                    "(camera above each object), then pick each selected object (default: all, "
                    "nearest first) and place it in the tray. Writes a report JSON, PNG "
                    "snapshots and an MP4.")
    p.add_argument("--scene", choices=["reference", "random", "sparse", "packed", "pile"], default="reference",
                   help="reference (method.md §8), random/sparse (primitives, 12 cm apart), packed or pile "
                        "(VGN/GIGA clutter protocols of --objects)")
    p.add_argument("--objects", default="builtin", metavar="builtin|DIR",
                   help="object set of packed/pile scenes: the built-in set or a folder of "
                        "URDF (VGN layout) / OBJ / STL objects")
    p.add_argument("--seed", type=non_negative_int, default=0, help="random scene seed")
    p.add_argument("--declutter", action="store_true",
                   help="clear the table one pick at a time, looking again after each attempt "
                        "(ends when nothing graspable is proposed or after 2 failures in a row)")
    p.add_argument("--pick", action="append", default=None, metavar="DESCRIPTION",
                   help='pick the object a short description names, after the scan (repeatable, '
                        'in order): --pick "the red mug" --pick "the tallest box"; colour, shape '
                        '(box, cylinder/can, mug, bottle, object) and size words (small, large, '
                        'tallest, nearest); not with --select or --declutter')
    _add_pick_options(p, "out/run")


LOG_LEVELS = ["DEBUG", "INFO", "WARNING", "ERROR"]


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="grasp-pipeline", description=__doc__.splitlines()[0])
    parser.add_argument("--log-level", default="INFO",
                        choices=LOG_LEVELS, help="logging level (also accepted after the sub-command)")
    sub = parser.add_subparsers(dest="command", required=True)
    demo = sub.add_parser("demo", help="run the default headless demo (reference scene, out/demo)",
                          description="The full run on the reference scene (method.md §8): rough view, "
                                      "scan, all three objects into the tray. Same options as run.")
    demo.set_defaults(seed=0)
    _add_pick_options(demo, "out/demo")
    _add_run(sub)
    _add_bench(sub)
    _add_record(sub)
    _add_eval(sub)
    _add_train(sub)
    _add_perceive(sub)
    return parser


def _print_json(result: dict) -> None:
    from .report.serialize import dumps

    print(dumps(result, sort_keys=True))


def _bench_sim(args: argparse.Namespace) -> None:
    from .bench.sim_bench import run_sim_benchmark

    _print_json(run_sim_benchmark(
        seconds=args.seconds, json_path=args.json,
        pick_scene=None if args.pick_scene == "none" else args.pick_scene, pick_seed=args.pick_seed,
        pick_objects=args.pick_objects, overrides=(args.config, args.sets)))


def _run_bench(args: argparse.Namespace) -> int:
    """The ``bench`` sub-commands; the exit code (1 when no scene or round of ``bench grasp`` /
    ``bench clutter`` ran to its end: status ``failed``)."""
    if args.bench == "perception":
        from .bench.perception_bench import run_perception_benchmark

        _print_json(run_perception_benchmark(
            frames=args.frames, json_path=args.json,
            baseline_frames=0 if args.no_baseline else args.baseline_frames))
    elif args.bench == "sim":
        _bench_sim(args)
    elif args.bench == "planning":
        from .bench.planning_bench import run_planning_benchmark

        _print_json(run_planning_benchmark(scenes=args.scenes, seed=args.seed,
                                           json_path=args.json, overrides=(args.config, args.sets),
                                           hard_pairs=args.hard, hard_only=args.hard_only))
    elif args.bench == "grasp":
        from .bench.grasp_bench import headline, run_grasp_benchmark

        result = run_grasp_benchmark(scenes=args.scenes, seed=args.seed, workers=args.workers,
                                     json_path=args.json, out_dir=args.out,
                                     progress=not args.no_progress,
                                     scene_timeout_s=args.scene_timeout,
                                     overrides=(args.config, args.sets),
                                     backend=args.backend, address=args.address)
        print(headline(result))
        print(f"JSON: {args.json}\nsummary: {result['summary']}")
        return 1 if result["status"] == "failed" else 0
    elif args.bench == "clutter":
        from .bench.clutter_bench import headline as clutter_headline
        from .bench.clutter_bench import run_clutter_benchmark

        result = run_clutter_benchmark(
            protocol=args.protocol, objects=args.objects, rounds=args.rounds, seeds=args.seed,
            workers=args.workers, json_path=args.json, out_dir=args.out,
            progress=not args.no_progress, round_timeout_s=args.round_timeout,
            overrides=(args.config, args.sets), backend=args.backend, address=args.address,
            rerun_dir=args.rerun)
        print(clutter_headline(result))
        print(f"JSON: {args.json}\nsummary: {result['summary']}")
        return 1 if result["status"] == "failed" else 0
    elif args.bench == "workers":
        from .bench.workers_bench import run_workers_benchmark

        _print_json(run_workers_benchmark(scenes=args.scenes, seed=args.seed, workers=args.workers,
                                          json_path=args.json, out_dir=args.out,
                                          progress=not args.no_progress,
                                          overrides=(args.config, args.sets)))
    elif args.bench == "frames":
        from .bench.frames_bench import run_frames_benchmark

        _print_json(run_frames_benchmark(scenes=args.scenes, seed=args.seed, workers=args.workers,
                                         json_path=args.json, out_dir=args.out,
                                         progress=not args.no_progress,
                                         overrides=(args.config, args.sets)))
    return 0


def _run(args: argparse.Namespace) -> int:
    if args.command == "demo":
        from .demo import run_demo

        return run_demo(args)
    if args.command == "run":
        from .app.run_command import run_command

        return run_command(args)
    if args.command == "bench":
        return _run_bench(args)
    if args.command == "record":
        from .dataset.record_command import record_main

        return record_main(args)
    if args.command == "eval":
        from .learning.eval_command import eval_main

        return eval_main(args)
    if args.command == "train":
        from .learning.train_command import train_main

        return train_main(args)
    if args.command == "perceive":
        from .perceive import run_perceive

        run_perceive(args.file, T_world_camera=args.T_world_camera, up=args.up,
                     json_path=args.json, png_path=args.png, config_file=args.config,
                     sets=args.sets, max_range_m=args.max_range_m, crop=args.crop)
        return 0
    raise AssertionError(f"unhandled command {args.command}")


def _split_log_level(argv: list[str] | None) -> tuple[Optional[str], list[str]]:
    """``--log-level`` may stand before or after the sub-command: take it out wherever it is."""
    pre = argparse.ArgumentParser(add_help=False)
    pre.add_argument("--log-level", choices=LOG_LEVELS, default=None)
    known, rest = pre.parse_known_args(sys.argv[1:] if argv is None else argv)
    return known.log_level, rest


def _uses_mujoco(args: argparse.Namespace) -> bool:
    return args.command in ("run", "demo", "record", "eval") or (args.command == "bench" and args.bench != "perception")


def main(argv: list[str] | None = None) -> int:
    level, rest = _split_log_level(argv)
    args = build_parser().parse_args(rest)
    if level is not None:
        args.log_level = level
    from .logs import setup_logging

    setup_logging(getattr(logging, args.log_level))
    if _uses_mujoco(args):  # before anything imports mujoco: the GL backend is chosen then
        from .sim.gl_backend import configure_gl

        configure_gl()
    try:
        return _run(args)
    except GraspPipelineError as exc:
        log.error("%s", shorten(str(exc)))
        return 2
    except KeyboardInterrupt:
        log.error("interrupted")
        return 130


if __name__ == "__main__":
    sys.exit(main())
