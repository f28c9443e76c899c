"""Command-line options shared by the sub-commands of ``grasp-pipeline`` (:mod:`.cli`) and the
benchmarks' arguments (:mod:`.bench.arguments`): argparse types that refuse bad numbers with a
clear message, ``--config/--set`` and ``--backend/--address``."""

from __future__ import annotations

import argparse


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


def add_config_options(p: argparse.ArgumentParser, sections: str, example: str) -> None:
    """``--config FILE`` and repeatable ``--set name=value`` (see grasp_pipeline.settings)."""
    p.add_argument("--config", default=None, metavar="FILE",
                   help=f"YAML with one section per parameter set ({sections}) overriding the defaults")
    p.add_argument("--set", dest="sets", action="append", default=[], metavar="NAME=VALUE",
                   help=f"override one parameter (repeatable), e.g. --set {example}")


def add_backend_options(p: argparse.ArgumentParser) -> None:
    """``--backend local|ray`` and ``--address`` of the commands that fan out."""
    p.add_argument("--backend", choices=["local", "ray"], default="local",
                   help="local: spawned processes on this machine; ray: Ray tasks (pip install "
                        "'grasp_pipeline[ray]'), a local Ray instance with --workers CPUs unless "
                        "--address joins a cluster")
    p.add_argument("--address", default=None, metavar="HOST:PORT",
                   help="with --backend ray: the Ray cluster to join (e.g. 10.0.0.5:6379)")
