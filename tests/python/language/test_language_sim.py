"""The resolver on a simulated table: the real camera (colour + depth), the real perception and
active scan; descriptions resolve against what was *perceived*. Ground truth (the objects'
names, categories, colours, poses) is read only to check the answers."""

import numpy as np
import pytest

from grasp_pipeline.app.sim_system import SECTIONS, build_system
from grasp_pipeline.language import (AmbiguousDescriptionError, NoMatchError, ObservationRecorder,
                                     perceive_objects, resolve)
from grasp_pipeline.objects.builtin import builtin_object
from grasp_pipeline.settings import load_settings
from grasp_pipeline.sim.ground_truth import object_truths
from grasp_pipeline.sim.scene_spec import ObjectSpec, SceneSpec
from grasp_pipeline.sim.work_cell import table_top_z_m

#: builtin object → (x, y) on the table [m]
PLACES = {"red_mug": (0.45, -0.13), "tall_bottle": (0.44, 0.02), "slim_can": (0.47, 0.15),
          "red_cube": (0.59, -0.07), "small_blue_cube": (0.60, 0.09)}


def _scene(settings) -> SceneSpec:
    top = table_top_z_m()
    objects = []
    for i, (name, (x, y)) in enumerate(PLACES.items()):
        m = builtin_object(name)
        z = top + 0.5 * float(m.extents_m()[2]) + 0.0005
        objects.append(ObjectSpec(name, "mesh", tuple(float(e) for e in m.extents_m()), (x, y, z),
                                  yaw_rad=0.4 * i, rgba=tuple(m.rgba), mesh=m, category=m.category))
    from grasp_pipeline.robot.description import READY_Q

    return SceneSpec("language", tuple(objects), top, tuple(float(v) for v in READY_Q))


@pytest.fixture(scope="module")
def seen():
    """(perceived objects, true object name → true (x, y)) after the rough view and the scan."""
    settings = load_settings(SECTIONS)
    system = build_system(_scene(settings), settings)
    try:
        obs = ObservationRecorder(settings.language).attach(system.events)
        system.rt.spin(settings.scan.rough_view_s)
        assert system.scanner.trigger().accepted
        system.rt.run(system.scanner.task, settings.scan.scan_timeout_s)
        system.rt.spin(settings.scan.settle_view_s)
        margin = settings.grasp.target_fixture_margin_m
        tracks = [t for t in system.loop.tracks()
                  if system.cell.pick_target_note(t.smoothed.center[:2], margin) is None]
        objects = perceive_objects(tracks, obs, settings.language)
        truth = {t.name: t.position_m[:2] for t in object_truths(system.world)}
    finally:
        system.close()
    return objects, truth


def _true_name(obj, truth) -> str:
    """The true object at the resolved object's perceived centre (for checking only)."""
    names = list(truth)
    d = [np.hypot(*(np.asarray(obj.center_m[:2]) - truth[n])) for n in names]
    assert min(d) < 0.02, f"#{obj.tid} at {obj.center_m[:2]} is no true object's centre"
    return names[int(np.argmin(d))]


@pytest.mark.parametrize("description, true_name", [
    ("the red mug", "red_mug"),            # colour + hollow, standing tall
    ("the red box", "red_cube"),
    ("the cyan bottle", "tall_bottle"),    # round, tall, narrowing
    ("the yellow can", "slim_can"),        # round flat top
    ("the small blue cube", "small_blue_cube"),
    ("the tallest object", "tall_bottle"),
])
def test_descriptions_name_the_object_ground_truth_says(seen, description, true_name):
    objects, truth = seen
    assert len(objects) == len(PLACES), [(o.tid, o.colour, o.shape) for o in objects]
    assert _true_name(resolve(description, objects), truth) == true_name


def test_nearest_is_nearest_to_the_robot_base(seen):
    objects, truth = seen
    nearest_true = min(truth, key=lambda n: float(np.hypot(*truth[n])))
    assert _true_name(resolve("the nearest object", objects), truth) == nearest_true


def test_refusals_list_what_was_seen(seen):
    objects, _ = seen
    with pytest.raises(AmbiguousDescriptionError, match=r"'the red object' fits 2 objects") as amb:
        resolve("the red object", objects)
    with pytest.raises(NoMatchError, match=r"'the purple mug': no purple mug seen; seen: #") as none:
        resolve("the purple mug", objects)
    for exc in (amb.value, none.value):
        assert "red mug" in str(exc) and "cyan bottle" in str(exc) and "yellow cylinder" in str(exc)
