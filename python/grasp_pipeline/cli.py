"""The ``grasp-pipeline`` command line.

Sub-commands:
  demo                      the default headless demo (see README)
  bench perception|sim|planning
                            benchmarks that print figures and write JSON

Every sub-command accepts ``--log-level``. Each sub-command's work lives in its
own module; this file only parses arguments and dispatches.
"""

from __future__ import annotations

import argparse
import json
import logging
import sys
from pathlib import Path

from .exceptions import GraspPipelineError

log = logging.getLogger("grasp_pipeline")


def _add_bench(sub: argparse._SubParsersAction) -> None:
    bench = sub.add_parser("bench", help="benchmarks (print figures, write JSON)")
    bsub = bench.add_subparsers(dest="bench", required=True)

    p = bsub.add_parser("perception", help="per-frame perception speed vs the Python baseline")
    p.add_argument("--frames", type=int, default=50, help="frames to time (default 50)")
    p.add_argument("--json", type=Path, required=True, help="where to write the JSON result")
    p.add_argument("--baseline-frames", type=int, default=5,
                   help="frames for the slow Python/Open3D baseline (default 5)")
    p.add_argument("--no-baseline", action="store_true",
                   help="skip the baseline (then no speedup is reported)")

    s = bsub.add_parser("sim", help="simulation real-time factors")
    s.add_argument("--seconds", type=float, default=5.0, help="simulated seconds")
    s.add_argument("--json", type=Path, required=True)

    pl = bsub.add_parser("planning", help="planning success / speed on random scenes")
    pl.add_argument("--scenes", type=int, default=50)
    pl.add_argument("--seed", type=int, default=0)
    pl.add_argument("--json", type=Path, required=True)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="grasp-pipeline", description=__doc__.splitlines()[0])
    parser.add_argument("--log-level", default="INFO",
                        choices=["DEBUG", "INFO", "WARNING", "ERROR"], help="logging level")
    sub = parser.add_subparsers(dest="command", required=True)
    sub.add_parser("demo", help="run the default headless demo")
    _add_bench(sub)
    return parser


def _print_json(result: dict) -> None:
    print(json.dumps(result, indent=2, sort_keys=True))


def _run(args: argparse.Namespace) -> int:
    if args.command == "demo":
        from .demo import run_demo

        return run_demo()
    if args.command == "bench":
        if args.bench == "perception":
            from .bench.perception_bench import run_perception_benchmark

            _print_json(run_perception_benchmark(
                frames=args.frames, json_path=args.json,
                baseline_frames=0 if args.no_baseline else args.baseline_frames))
        elif args.bench == "sim":
            from .bench.sim_bench import run_sim_benchmark

            _print_json(run_sim_benchmark(seconds=args.seconds, json_path=args.json))
        elif args.bench == "planning":
            from .bench.planning_bench import run_planning_benchmark

            _print_json(run_planning_benchmark(scenes=args.scenes, seed=args.seed,
                                               json_path=args.json))
        return 0
    raise AssertionError(f"unhandled command {args.command}")


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    logging.basicConfig(level=getattr(logging, args.log_level),
                        format="%(asctime)s %(levelname)s %(name)s: %(message)s")
    try:
        return _run(args)
    except GraspPipelineError as exc:
        log.error("%s", exc)
        return 2


if __name__ == "__main__":
    sys.exit(main())
