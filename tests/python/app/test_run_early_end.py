"""A run that ends before its world is built still writes its report: interrupted (Ctrl-C or
SIGTERM while the scene's objects load, in real processes: :mod:`faults` signals at the start
of ``object_set``) or failed (a bad object set). A second writer of the same ``--out`` is
named in the report's warnings; the run's own output marker is gone afterwards."""

from __future__ import annotations

import json
import os
import socket
import sys
from pathlib import Path

import pytest

from grasp_pipeline.cli import main
from grasp_pipeline.report.output_lock import PREFIX, SUFFIX, _process_start

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from faults import clean_env, fault_env, leftovers, start  # noqa: E402

RUN = ["run", "--scene", "packed", "--objects", "builtin", "--no-video", "--out", "out"]


def _other_writer(folder: Path) -> Path:
    """The marker of another live writer of ``folder`` (this test process)."""
    folder.mkdir(parents=True)
    marker = folder / f"{PREFIX}{socket.gethostname()}-{os.getpid()}{SUFFIX}"
    marker.write_text(json.dumps({"pid": os.getpid(), "host": socket.gethostname(), "command": "run",
                                  "process_start": _process_start(os.getpid()), "started": "then"}))
    return marker


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    procs = {}
    for sig, target in (("SIGINT", "group"), ("SIGTERM", "main")):
        d = tmp_path_factory.mktemp(sig)
        marker = _other_writer(d / "out")
        env = clean_env(d, fault_env(d, "grasp_pipeline.objects.catalog:object_set", sig, target))
        procs[sig] = (d, marker, start(RUN, d, env))
    out = {}
    for sig, (d, marker, p) in procs.items():
        stdout, stderr = p.communicate(timeout=300)
        out[sig] = (d, marker, p.returncode, stdout, stderr)
    return out


@pytest.mark.parametrize("sig", ["SIGINT", "SIGTERM"])
def test_a_run_interrupted_while_its_objects_load_writes_its_report(runs, sig):
    d, marker, _, stdout, stderr = runs[sig]
    assert (d / "fault_fired").exists(), stderr[-3000:]
    report = json.loads((d / "out" / "report.json").read_text())
    assert report["status"] == "interrupted" and "objects loading" in report["error"], report
    assert report["picks"] == [] and report["rough"] is None
    assert any("another grasp-pipeline process is writing to out" in w for w in report["warnings"])
    assert "Traceback" not in stderr
    assert leftovers(d) == [str(marker.relative_to(d))]  # the other writer's marker only


def test_a_run_interrupted_while_its_objects_load_exits_130(runs):
    assert [runs[s][2] for s in ("SIGINT", "SIGTERM")] == [130, 130]


def test_a_bad_object_set_is_a_one_line_error_and_a_failed_report(tmp_path, caplog):
    rc = main(["run", "--scene", "packed", "--objects", str(tmp_path / "nowhere"), "--no-video",
               "--out", str(tmp_path / "out")])
    assert rc == 2 and "nowhere: no such file or folder" in caplog.text
    report = json.loads((tmp_path / "out" / "report.json").read_text())
    assert report["status"] == "failed" and "nowhere" in report["error"]
    assert leftovers(tmp_path) == []
