"""Run a snippet in a fresh interpreter, so that a crash (abort, segfault, double free)
fails one test instead of killing the whole pytest run."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

HERE = Path(__file__).resolve().parent


def run_isolated(code: str, timeout_s: float = 120.0) -> subprocess.CompletedProcess:
    """Run ``code`` with this interpreter and this process's import path (plus this folder)."""
    env = dict(os.environ)
    paths = [str(HERE)] + [p for p in sys.path if p]
    env["PYTHONPATH"] = os.pathsep.join(paths)
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True,
                          text=True, timeout=timeout_s, env=env)


def describe(res: subprocess.CompletedProcess) -> str:
    """A failure message: how the child ended and the tail of its output."""
    how = f"signal {-res.returncode}" if res.returncode < 0 else f"exit code {res.returncode}"
    return f"child ended with {how}\nstdout: {res.stdout[-2000:]}\nstderr: {res.stderr[-2000:]}"
