"""Ctrl-C / SIGTERM inside ``interrupts_raise`` are counted, so a loop over library calls raises
an interrupt again when the library swallowed it (trimesh catches BaseException while it reads a
textured OBJ: a SIGTERM landing there was lost and the run went on)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest
import trimesh

from grasp_pipeline import signals
from grasp_pipeline.objects import mesh_object


def _swallowing_load(path, **kwargs):
    """A library step that swallows the interrupt it receives."""
    try:
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(0.05)
    except BaseException:  # noqa: BLE001 (what the library does)
        pass
    return path.name


def test_an_interrupt_a_library_swallows_is_raised_again_by_the_loader(tmp_path, monkeypatch):
    for name in ("a", "b", "c"):
        trimesh.creation.box(extents=(0.03, 0.03, 0.03)).export(tmp_path / f"{name}.obj")
    monkeypatch.setattr(mesh_object, "load_object", _swallowing_load)
    with signals.interrupts_raise():
        with pytest.raises(KeyboardInterrupt, match="loading the objects"):
            mesh_object.load_object_dir(tmp_path)
    assert signal.getsignal(signal.SIGTERM) is not signals._handler  # restored


def test_outside_the_block_nothing_changes():
    before = signal.getsignal(signal.SIGTERM)
    with signals.interrupts_raise():
        assert signal.getsignal(signal.SIGTERM) is signals._handler
    assert signal.getsignal(signal.SIGTERM) is before


def test_held_signals_arrive_once_after_the_block():
    reached_end = False
    with signals.interrupts_raise():
        mark = signals.received()
        with pytest.raises(KeyboardInterrupt):
            with signals.held():
                os.kill(os.getpid(), signal.SIGTERM)
                os.kill(os.getpid(), signal.SIGTERM)
                time.sleep(0.05)
                reached_end = True
        assert signals.received() == mark + 1
    assert reached_end
    assert signal.SIGTERM not in signal.pthread_sigmask(signal.SIG_BLOCK, [])  # mask restored
    assert signal.getsignal(signal.SIGTERM) is not signals._handler           # handler restored


def _blocked_in_a_new_process() -> set[int]:
    code = "import signal; print(*[int(s) for s in signal.pthread_sigmask(signal.SIG_BLOCK, [])])"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return {int(s) for s in out.stdout.split()}


def test_a_process_started_while_they_are_held_starts_with_them_blocked():
    with signals.held():
        inside = _blocked_in_a_new_process()
    assert {int(signal.SIGINT), int(signal.SIGTERM)} <= inside
    assert not {int(signal.SIGINT), int(signal.SIGTERM)} & _blocked_in_a_new_process()
