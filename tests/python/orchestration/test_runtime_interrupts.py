"""A Ctrl-C that a C extension turns into another error while a task runs (a pybind11 module's
import interrupted half-way reports ``ImportError: initialization failed``) still ends the run as
an interrupt: the runtime raises ``KeyboardInterrupt`` instead of logging a failed task; so does an
interrupt a task swallowed. A task that is closed or interrupted makes no cleanup motion."""

from __future__ import annotations

import logging
import os
import signal
import time

import pytest

from grasp_pipeline import signals
from grasp_pipeline.orchestration import Runtime
from grasp_pipeline.orchestration.runtime import then_cleanup


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


def _swallowing_task():
    """A task whose library step swallows the interrupt it receives (``except BaseException``)."""
    yield
    try:
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(0.05)
    except BaseException:  # noqa: BLE001 (what such a library does)
        pass
    yield


def test_an_interrupt_a_task_swallowed_is_raised_by_the_step():
    rt = Runtime(Clock())
    rt.start("scan", _swallowing_task())
    with signals.interrupts_raise():
        rt.step()
        with pytest.raises(KeyboardInterrupt, match="task scan ran"):
            rt.step()


class _Moves:
    """What a task did, in order."""

    def __init__(self) -> None:
        self.done: list[str] = []

    def move(self, name: str, fail: bool = False):
        yield
        self.done.append(name)
        if fail:
            raise RuntimeError(f"{name} failed")

    def body(self, fail: bool = False, interrupt: bool = False):
        yield from self.move("probe", fail)
        if interrupt:
            raise KeyboardInterrupt("signal 15")
        yield from self.move("look")
        return "result"


def _drive(gen):
    while True:
        try:
            next(gen)
        except StopIteration as stop:
            return stop.value


def test_the_cleanup_follows_the_body_and_its_errors():
    moves = _Moves()
    assert _drive(then_cleanup(moves.body(), lambda: moves.move("return"))) == "result"
    assert moves.done == ["probe", "look", "return"]
    moves = _Moves()
    with pytest.raises(RuntimeError, match="probe failed"):
        _drive(then_cleanup(moves.body(fail=True), lambda: moves.move("return")))
    assert moves.done == ["probe", "return"]
    moves = _Moves()
    _drive(then_cleanup(moves.body(), lambda: None))  # None: no cleanup
    assert moves.done == ["probe", "look"]


def test_a_closed_or_interrupted_task_makes_no_cleanup_motion():
    moves = _Moves()
    with pytest.raises(KeyboardInterrupt):
        _drive(then_cleanup(moves.body(interrupt=True), lambda: moves.move("return")))
    assert moves.done == ["probe"]
    moves = _Moves()
    task = then_cleanup(moves.body(), lambda: moves.move("return"))
    next(task)
    next(task)
    task.close()  # (a task that yields while closed raises RuntimeError here)
    assert moves.done == ["probe"]
