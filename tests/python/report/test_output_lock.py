"""The output marker: a second live writer of a folder is warned about, a dead one's marker is
removed silently, and a claim removes only its own marker."""

from __future__ import annotations

import json
import os
import socket
import subprocess

from grasp_pipeline.report.output_lock import PREFIX, SUFFIX, _process_start, claim_output, output_claim


def _marker(folder, pid, **extra):
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{PREFIX}{socket.gethostname()}-{pid}{SUFFIX}"
    path.write_text(json.dumps({"pid": pid, "host": socket.gethostname(), "command": "run",
                                "started": "earlier", **extra}))
    return path


def _markers(folder):
    return sorted(p.name for p in folder.glob(f"{PREFIX}*"))


def test_a_live_writer_is_warned_about_and_its_marker_kept(tmp_path):
    other = subprocess.Popen(["sleep", "30"])
    try:
        theirs = _marker(tmp_path, other.pid, process_start=_process_start(other.pid))
        with output_claim(tmp_path, "bench clutter") as claim:
            assert f"pid {other.pid}" in claim.warning and "give each command its own --out" in claim.warning
            assert len(_markers(tmp_path)) == 2
        assert _markers(tmp_path) == [theirs.name]
    finally:
        other.kill()
        other.wait()


def test_a_dead_writer_or_a_reused_pid_is_stale_and_removed(tmp_path):
    dead = subprocess.Popen(["true"])
    dead.wait()
    _marker(tmp_path, dead.pid)                                  # process gone
    _marker(tmp_path, os.getppid(), process_start="-1")          # pid alive, but another process
    (tmp_path / f"{PREFIX}garbage{SUFFIX}").write_text("{not json")
    claim = claim_output(tmp_path, "run")
    assert claim.warning == ""
    assert _markers(tmp_path) == [claim.marker.name]
    claim.release()
    assert _markers(tmp_path) == []


def test_an_unwritable_folder_is_not_marked_and_the_command_goes_on(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    claim = claim_output(blocker / "out", "run")
    assert claim.marker is None and claim.warning == ""
    claim.release()
