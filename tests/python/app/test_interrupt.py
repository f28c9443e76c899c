"""Ctrl-C or SIGTERM during a run: the arm holds, the report says "interrupted" and keeps
everything done so far; it replaces an earlier complete report atomically."""

import json
import signal
import subprocess
import time

import pytest

from .test_entry_points import EXE, clean_env


def _as_from_a_terminal() -> None:
    """The child's SIGINT as a foreground process of an interactive shell has it (Ctrl-C
    interrupts). A runner started in the background by a non-interactive shell passes SIGINT on
    ignored, and an ignored SIGINT is kept ignored by Python (and by ``nohup``-style launches):
    without this the test measured the runner, not the product."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_a_signal_mid_run_leaves_an_interrupted_report(sig, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "report.json").write_text(json.dumps({"status": "complete", "picks": [1, 2, 3]}))
    proc = subprocess.Popen([str(EXE), "run", "--scene", "reference", "--no-video", "--out", "out"],
                            cwd=tmp_path, env=clean_env(None, tmp_path), stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, stdin=subprocess.DEVNULL,
                            preexec_fn=_as_from_a_terminal)
    seen = ""
    t_end = time.monotonic() + 600
    while "grasp stage PRE_GRASP" not in seen and time.monotonic() < t_end:
        line = proc.stderr.readline()
        if not line:
            break
        seen += line
    assert "grasp stage PRE_GRASP" in seen, seen[-3000:]
    proc.send_signal(sig)
    _, rest = proc.communicate(timeout=120)
    assert proc.returncode == 130, (seen + rest)[-3000:]
    assert "Traceback" not in rest
    report = json.loads((out / "report.json").read_text())
    assert report["status"] == "interrupted"
    assert report["scan"]["completed"] and len(report["rough"]["tracks"]) == 3
    assert "interrupted" in report["error"]


def test_an_interrupted_benchmark_writes_what_it_finished(tmp_path):
    proc = subprocess.Popen([str(EXE), "bench", "grasp", "--scenes", "3", "--seed", "5", "--workers", "1",
                             "--json", "g.json", "--out", "bg", "--no-progress", "--set",
                             "sim.object_count=[1,1]"],
                            cwd=tmp_path, env=clean_env(None, tmp_path), stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, stdin=subprocess.DEVNULL,
                            preexec_fn=_as_from_a_terminal)
    seen, t_end = "", time.monotonic() + 600
    while seen.count("grasp stage PRE_GRASP") < 2 and time.monotonic() < t_end:  # in scene 2
        line = proc.stderr.readline()
        if not line:
            break
        seen += line
    proc.send_signal(signal.SIGINT)
    _, rest = proc.communicate(timeout=180)
    assert proc.returncode == 130, (seen + rest)[-3000:]
    out = json.loads((tmp_path / "g.json").read_text())
    assert out["status"] == "interrupted" and 1 <= out["scenes_finished"] < 3
