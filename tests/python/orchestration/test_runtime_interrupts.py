"""A Ctrl-C that a C extension turns into another error while a task runs (a pybind11 module's
import interrupted half-way reports ``ImportError: initialization failed``) still ends the run as
an interrupt: the runtime raises ``KeyboardInterrupt`` instead of logging a failed task."""

from __future__ import annotations

import logging
import os
import signal
import time

import pytest

from grasp_pipeline import signals
from grasp_pipeline.orchestration import Runtime


class Clock:
    def __init__(self) -> None:
        self.time_s, self.timestep_s = 0.0, 0.01

    def step(self, n: int = 1) -> None:
        self.time_s += n * self.timestep_s


def _import_interrupted():
    """A task whose library import is interrupted and reports an ImportError instead."""
    yield
    try:
        os.kill(os.getpid(), signal.SIGTERM)  # (SIGINT may be ignored: a background job)
        time.sleep(0.05)
    except KeyboardInterrupt as exc:
        raise ImportError("initialization failed") from exc
    yield


def _plain_failure():
    yield
    raise ImportError("no module named nothing")


def test_an_interrupt_turned_into_an_error_inside_a_task_is_an_interrupt(caplog):
    rt = Runtime(Clock())
    rt.start("scan", _import_interrupted())
    with signals.interrupts_raise(), caplog.at_level(logging.ERROR):
        rt.step()
        with pytest.raises(KeyboardInterrupt):
            rt.step()
    assert "failed" not in caplog.text


def test_a_task_error_without_a_signal_is_still_a_failed_task(caplog):
    rt = Runtime(Clock())
    task = rt.start("scan", _plain_failure())
    with signals.interrupts_raise(), caplog.at_level(logging.ERROR):
        rt.step()
        rt.step()
    assert task.done and isinstance(task.error, ImportError)
    assert "task scan failed" in caplog.text
