"""A run interrupted by Ctrl-C / SIGTERM writes its report saying so; a further signal while the run
closes and writes it (a benchmark stopping its workers, an impatient user) is raised only once
the report is on disk."""

from __future__ import annotations

import json
import os
import signal
import time
from types import SimpleNamespace

import pytest

from grasp_pipeline import signals
from grasp_pipeline.app import run_loop
from grasp_pipeline.results import RunReport


class _System:
    """The parts of a robot system the run's ending uses; closing it takes a second signal."""

    def __init__(self) -> None:
        self.robot = SimpleNamespace(time_s=1.0, hold=lambda: None)
        self.motion = SimpleNamespace(plans=[])
        self.events = SimpleNamespace(failures=[])
        self.closed = False

    def close(self) -> None:
        os.kill(os.getpid(), signal.SIGTERM)  # (SIGINT may be ignored: a background job)
        time.sleep(0.05)
        self.closed = True


def _interrupted_stages(*args) -> None:
    raise KeyboardInterrupt("signal 2")


def test_a_second_signal_waits_until_the_report_is_written(tmp_path, monkeypatch):
    monkeypatch.setattr(run_loop, "_stages", _interrupted_stages)
    system, report = _System(), RunReport(scene={}, settings={})
    with signals.interrupts_raise(), pytest.raises(KeyboardInterrupt):
        run_loop.drive(system, None, report, SimpleNamespace(grasp_source=object()),
                       run_loop.Recorders, 0.0, tmp_path / "report.json")
    assert system.closed
    assert json.loads((tmp_path / "report.json").read_text())["status"] == "interrupted"
