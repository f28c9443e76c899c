"""``make demo`` / ``grasp-pipeline demo``: the full run on the reference scene, headless.

Rough view, active scan, then all three objects picked into the tray; prints where the
report, the snapshots and the video are (default ``out/demo``). Takes the same options as
``run`` except the scene.
"""

from __future__ import annotations

from pathlib import Path

DEMO_OUT = Path("out/demo")


def run_demo(args) -> int:
    from .app.run_command import run_command

    return run_command(args, scene="reference")
