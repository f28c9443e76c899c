"""Frames on demand in the real pipeline (reference scene, real physics and planning): the
camera renders while the pipeline looks (rough view, scan dwell) and never during a motion;
liveness is judged on the looking clock — a long motion does not make perception stale, a
camera that delivers nothing while someone looks does."""

import numpy as np
import pytest

from grasp_pipeline.app.sim_system import SECTIONS, build_system
from grasp_pipeline.settings import load_settings
from grasp_pipeline.sim.scenes import reference_scene


@pytest.fixture(scope="module")
def system():
    settings = load_settings(SECTIONS)
    s = build_system(reference_scene(settings.sim), settings)
    s.captures = []  # (time_s, arm at the end of its trajectory) of every frame
    s.world.add_frame_listener(lambda f: s.captures.append((f.time_s, s.world.trajectory_done())))
    yield s
    s.close()


def test_the_rough_view_looks_and_locks_the_plane(system):
    system.rt.spin(0.5)
    assert system.loop.plane_locked
    assert len(system.captures) >= 14  # 0.5 s at 30 Hz


def test_the_scan_renders_only_while_dwelling_never_during_a_motion(system):
    before = len(system.captures)
    t0 = system.world.time_s
    assert system.scanner.trigger().accepted
    out = system.rt.run(system.scanner.task, 120.0)
    assert out.completed and out.returned_to_start and all(p.nadir for p in out.probes)
    during = system.captures[before:]
    assert during and all(at_rest for _, at_rest in during)  # dwell frames only
    # far fewer frames than 30 Hz over the scan (probes, dwells and the return)
    assert len(during) < 0.5 * 30.0 * (system.world.time_s - t0)


def test_a_motion_renders_nothing_and_does_not_make_perception_stale(system):
    before = len(system.captures)
    t0 = system.world.time_s
    q = np.array(system.world.q)
    q_far = q.copy()
    q_far[0] += 0.6
    for goal in (q_far, q):  # there and back: several seconds without looking
        system.rt.run(system.rt.start("move", system.motion.to_joints(goal)), 60.0)
    assert system.world.time_s - t0 > system.loop.config.stale_timeout_s
    assert len(system.captures) == before
    assert system.world.time_s - system.loop.last_frame_time_s() > system.loop.config.stale_timeout_s
    assert not system.loop.stale(system.world.time_s)


def test_a_camera_that_delivers_nothing_while_looking_is_stale(system):
    system.rt.spin(0.2)
    assert not system.loop.stale(system.world.time_s)
    real_poll = system.world.poll_frame
    system.world.poll_frame = lambda: None  # the camera dies
    try:
        system.rt.spin(1.0)
        assert not system.loop.stale(system.world.time_s)  # 1 s of looking < stale_timeout_s
        system.rt.spin(1.5, look=False)
        assert not system.loop.stale(system.world.time_s)  # not looking: nothing was due
        system.rt.spin(1.2)
        assert system.loop.stale(system.world.time_s)  # 2.2 s of looking without a frame
        assert system.loop.report_if_stale(system.world.time_s)
    finally:
        system.world.poll_frame = real_poll
    system.rt.spin(0.1)
    assert not system.loop.stale(system.world.time_s)
