"""The ``grasp-pipeline`` command line.

Sub-commands:
  demo                      the default headless demo: ``run`` on the reference scene
  run                       rough view, active scan, pick (and place) the selected objects
  bench perception|sim|planning|grasp|workers|frames|clutter|language
                            benchmarks that print figures and write JSON (one entry each
                            in grasp_pipeline.bench.registry)
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

from . import signals
from .cli_options import (add_backend_options, add_config_options, finite_float, non_negative_int,
                          positive_float, positive_int)
from .exceptions import GraspPipelineError
from .messages import shorten

log = logging.getLogger("grasp_pipeline")


def _add_bench(sub: argparse._SubParsersAction) -> None:
    """``bench <name>``: one sub-command per benchmark of :data:`~.bench.registry.BENCHMARKS`."""
    from .bench.registry import BENCHMARKS

    bench = sub.add_parser("bench", help="benchmarks (print figures, write JSON)")
    bsub = bench.add_subparsers(dest="bench", required=True)
    for b in BENCHMARKS.values():
        b.add_arguments(bsub.add_parser(b.name, help=b.help, description=b.description))


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
    add_backend_options(r)
    add_config_options(r, "record, env, scene_filter, obb, camera, sim, clutter, motion, scan, grasp",
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
    add_backend_options(e)
    add_config_options(e, "env, record, scene_filter, obb, camera, sim, clutter, motion, scan, grasp",
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
    add_config_options(t, "train, record", "train.dim_model=256")


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
    add_config_options(p, "scene_filter / obb / workspace", "cluster_eps=0.02")


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
    add_config_options(p, "scene_filter, obb, camera, sim, clutter, motion, scan, grasp, video, "
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


def _run_bench(args: argparse.Namespace) -> int:
    """``bench <name>``: its entry point, then what it prints; its exit code (1 when no scene or
    round of ``bench grasp`` / ``bench clutter`` ran to its end: status ``failed``)."""
    from .bench.registry import BENCHMARKS

    benchmark = BENCHMARKS[args.bench]
    return benchmark.report(benchmark.run(args), args)


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
    if args.command == "bench":
        from .bench.registry import BENCHMARKS

        return BENCHMARKS[args.bench].uses_mujoco
    return args.command in ("run", "demo", "record", "eval")


def main(argv: list[str] | None = None) -> int:
    level, rest = _split_log_level(argv)
    args = build_parser().parse_args(rest)
    if args.command != "train":  # thin products: the BLAS pool costs more than it gives
        from .blas_threads import blas_on_calling_thread

        blas_on_calling_thread()
    if level is not None:
        args.log_level = level
    from .logs import setup_logging

    setup_logging(getattr(logging, args.log_level))
    mark = signals.received()
    try:
        with signals.interrupts_raise():
            _prepare_process(args)
            return _run(args)
    except GraspPipelineError as exc:
        log.error("%s", shorten(str(exc)))
        return 2
    except KeyboardInterrupt:
        log.error("interrupted")
        return 130
    except Exception:
        if signals.received() == mark:  # not an import a Ctrl-C cut short: a real error
            raise
        log.error("interrupted")
        return 130


def _prepare_process(args: argparse.Namespace) -> None:
    if _uses_mujoco(args):  # before anything imports mujoco: the GL backend is chosen then
        from .process_memory import keep_large_allocations
        from .sim.gl_backend import configure_gl

        configure_gl()
        keep_large_allocations()


if __name__ == "__main__":
    sys.exit(main())
