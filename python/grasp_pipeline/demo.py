"""``make demo`` / ``grasp-pipeline demo``: the full run on the reference scene, headless.

Rough view, active scan, then all three objects picked into the tray; prints where the
report, the snapshots and the video are (``out/demo``).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from .orchestration.summary import run_command

DEMO_OUT = Path("out/demo")


def run_demo() -> int:
    args = argparse.Namespace(scene="reference", seed=0, select=None, out=DEMO_OUT,
                              json=DEMO_OUT / "report.json", no_video=False, no_scan=False,
                              config=None, sets=[])
    return run_command(args)
