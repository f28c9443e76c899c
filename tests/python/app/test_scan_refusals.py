"""The scan's refusals (method.md §6) and selection refusals on the live system."""

import numpy as np
import pytest

from grasp_pipeline.app.sim_system import SECTIONS, build_system
from grasp_pipeline.settings import load_settings
from grasp_pipeline.sim.scenes import reference_scene


@pytest.fixture()
def system():
    settings = load_settings(SECTIONS)
    s = build_system(reference_scene(settings.sim), settings)
    yield s
    s.close()


def test_scan_refused_before_the_plane_is_locked_then_while_running(system):
    # Camera geometry is known from start-up, but no frame has arrived: no plane yet.
    res = system.scanner.trigger()
    assert not res.accepted and "plane not locked" in res.message
    assert system.loop.select(0.56, -0.03).message == "nothing seen yet"
    system.rt.spin(0.3)  # a few frames: plane locked, objects tracked
    res = system.scanner.trigger()
    assert res.accepted and res.message == "scan started: probing 3 objects"
    system.rt.spin(0.5)  # the scan runs in the background
    status = system.scanner.status
    assert status["stage"] == "probing" and status["i"] == 1 and status["n"] == 3
    again = system.scanner.trigger()
    assert not again.accepted
    assert "already scanning (probing object 1/3" in again.message
    # Finish the scan; the state machine ends idle with i/N reset.
    result = system.rt.run(system.scanner.task, 120.0)
    assert result.completed and system.scanner.status == {"stage": "idle", "i": 0, "n": 0}


def test_grasp_refused_without_a_best_grasp(system):
    system.rt.spin(0.2)
    ok, msg = system.action.start()
    assert not ok and msg == "no best grasp yet"


def test_scan_refused_when_nothing_is_seen():
    settings = load_settings(SECTIONS)
    spec = reference_scene(settings.sim)
    from dataclasses import replace

    empty = replace(spec, objects=())
    s = build_system(empty, settings)
    try:
        s.rt.spin(0.3)
        res = s.scanner.trigger()
        assert not res.accepted and res.message == "scan refused: no objects seen"
    finally:
        s.close()


def test_stale_perception_makes_no_motion(system):
    system.rt.spin(0.3)
    system.world.remove_frame_listener(system.world._frame_listeners[0])  # upstream dies
    system.rt.spin(2.5)
    q0 = np.array(system.world.q)
    res = system.scanner.trigger()
    assert res.accepted
    out = system.rt.run(system.scanner.task, 10.0)
    assert "stale" in out.failure and not out.returned_to_start
    assert np.max(np.abs(np.array(system.world.q) - q0)) < 1e-3
    assert system.scanner.status["stage"] == "idle"
