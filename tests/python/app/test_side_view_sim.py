"""The scene volume and the side view in the real pipeline (reference scene, real camera,
physics, IK and planning): the rough view's frames carve free space and mark the objects'
tops; a target whose sides are unknown enough gets a view that the arm reaches, from which
the unknown part of its shell shrinks, and the arm comes back."""

import numpy as np
import pytest

from grasp_pipeline.app.sim_system import SECTIONS, build_system
from grasp_pipeline.orchestration.scanning.side_view import look_at_sides
from grasp_pipeline.perception.scene_volume import FREE, OCCUPIED, UNKNOWN
from grasp_pipeline.settings import load_settings
from grasp_pipeline.sim.scenes import reference_scene


@pytest.fixture(scope="module")
def system():
    # After the rough view alone the reference cubes' far faces are 15-25 % unknown (the
    # oblique start view); look at them from 10 %.
    settings = load_settings(SECTIONS, None, ["volume.side_view_unknown_fraction=0.1"])
    s = build_system(reference_scene(settings.sim), settings)
    s.rt.spin(settings.scan.rough_view_s)
    yield s
    s.close()


def test_the_rough_view_carves_the_space_above_the_table_and_marks_the_tops(system):
    vol, loop = system.loop.volume, system.loop
    assert vol.stats.frames_integrated >= 2 and vol.stats.frames_integrated < vol.stats.frames_offered
    for t in loop.tracks():
        e = t.smoothed
        top = np.asarray(e.center) + [0.0, 0.0, 0.5 * e.extents[2]]
        above = top + [0.0, 0.0, 0.05]
        inside = np.asarray(e.center)  # never seen: behind the surfaces
        assert vol.classify(np.array([top, above, inside])).tolist() == [OCCUPIED, FREE, UNKNOWN], t.tid


def test_a_side_view_reveals_the_far_side_and_comes_back(system):
    q0 = np.array(system.world.q)
    track = max(system.loop.tracks(), key=lambda t: system.side_view.coverage(t).worst)
    out = look_at_sides(system.side_view, track, 60.0)
    assert out.unknown_before >= 0.1
    assert out.moved and out.message == "", out.message
    assert out.unknown_after < 0.5 * out.unknown_before
    assert np.max(np.abs(np.array(system.world.q) - q0)) < 1e-2  # back at the start joints
    assert out.sim_s > 0 and out.cpu_s > 0
