"""The simulated commands run numpy's BLAS on the calling thread (set before numpy loads; a
value the user set is kept; too late once numpy is imported). In fresh interpreters."""

from __future__ import annotations

import os
import subprocess
import sys

CHECK = """
import os, sys
from grasp_pipeline.cli import main
rc = main(["perceive", "/nonexistent/cloud.pcd", "--json", "/nonexistent/out.json", "--up", "0", "0", "1"])
import numpy
print(rc, os.environ.get("OPENBLAS_NUM_THREADS"))
"""


def _python(code: str, **env) -> str:
    base = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"}
    out = subprocess.run([sys.executable, "-c", code], env={**base, **env}, capture_output=True,
                         text=True, timeout=120)
    assert out.returncode == 0, out.stderr[-2000:]
    return out.stdout.split()


def test_a_command_sets_one_blas_thread_before_numpy_loads():
    assert _python(CHECK) == ["2", "1"]


def test_the_users_setting_is_kept():
    assert _python(CHECK, OPENBLAS_NUM_THREADS="3") == ["2", "3"]


def test_after_numpy_is_imported_nothing_changes():
    code = "import numpy\nfrom grasp_pipeline.blas_threads import blas_on_calling_thread as f\n" \
           "import os\nprint(f(), os.environ.get('OPENBLAS_NUM_THREADS'))"
    assert _python(code) == ["False", "None"]
