"""The command line ends an interrupted command with "interrupted" and exit code 130, also when the
signal landed in an import that a C extension turned into ``ImportError: initialization failed``
(as a Ctrl-C does while a pybind11 module initialises); an error without a signal stays an error.
In fresh interpreters (the command sets up logging and signal handlers)."""

from __future__ import annotations

import subprocess
import sys

import pytest

CODE = """
import os, signal, sys, time
from grasp_pipeline import cli

def interrupted_import(args):
    try:
        if {signal}:
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(0.5)
    except KeyboardInterrupt as exc:
        raise ImportError("initialization failed") from exc
    raise ImportError("initialization failed")

cli._run = interrupted_import
sys.exit(cli.main(["perceive", "cloud.pcd", "--json", "out.json", "--up", "0", "0", "1"]))
"""


@pytest.mark.parametrize("signalled", [True, False], ids=["signal", "no signal"])
def test_an_import_cut_short_by_a_signal_is_an_interrupt(signalled, tmp_path):
    out = subprocess.run([sys.executable, "-c", CODE.format(signal=signalled)], cwd=tmp_path,
                         capture_output=True, text=True, timeout=120)
    if signalled:
        assert out.returncode == 130 and "Traceback" not in out.stderr, out.stderr[-2000:]
        assert "interrupted" in out.stderr
    else:
        assert out.returncode == 1 and "ImportError: initialization failed" in out.stderr
