"""Memory settings of simulation processes: applied in a fresh process, switched off by the
environment variable."""

from __future__ import annotations

import subprocess
import sys

from grasp_pipeline import process_memory

_PROBE = """
import gc, sys
from grasp_pipeline.process_memory import keep_large_allocations
applied = keep_large_allocations()
print(applied, gc.get_threshold()[0])
"""


def _probe(env_value: str | None) -> list[str]:
    import os

    env = dict(os.environ)
    env.pop(process_memory.ENV_VAR, None)
    if env_value is not None:
        env[process_memory.ENV_VAR] = env_value
    out = subprocess.run([sys.executable, "-c", _PROBE], env=env, capture_output=True, text=True,
                         check=True)
    return out.stdout.split()


def test_settings_apply_in_a_fresh_process_on_glibc():
    applied, threshold = _probe(None)
    if sys.platform.startswith("linux"):
        assert applied == "True"
    assert int(threshold) == process_memory.GC_YOUNG_THRESHOLD


def test_the_environment_variable_switches_them_off():
    applied, threshold = _probe("0")
    assert applied == "False" and int(threshold) == 700
