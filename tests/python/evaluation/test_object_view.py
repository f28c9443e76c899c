"""The picture of where a failed attempt's object went: aimed at its true position, with the
tray in view when it is near it; written for failures after the grasp only."""

import numpy as np
import pytest

from grasp_pipeline.evaluation.object_view import ObjectView, view_of
from grasp_pipeline.orchestration.events import PickEvent
from grasp_pipeline.report.failure_recorder import FailureSnapshotRecorder
from grasp_pipeline.results import PickResult
from grasp_pipeline.sim.ground_truth import object_body_id
from grasp_pipeline.sim.world import SimWorld


@pytest.fixture(scope="module")
def world():
    w = SimWorld()  # the reference scene
    yield w
    w.close()


def _move(world, name, xyz):
    bid = object_body_id(world, name)
    adr = world.model.jnt_qposadr[world.model.body_jntadr[bid]]
    world.data.qpos[adr:adr + 3] = xyz
    import mujoco

    mujoco.mj_kinematics(world.model, world.data)


def test_an_object_near_the_tray_is_shown_with_the_tray(world):
    tray = world.work_cell.tray_center_m
    _move(world, "red_cube", tray + [0.2, 0.0, 0.03])  # fell just outside the tray
    v = view_of(world, "red_cube")
    assert np.allclose(v["lookat_m"], tray + [0.1, 0.0, 0.015])
    assert v["distance_m"] >= 0.7
    assert view_of(world, "no_such_object") is None


def test_an_object_far_from_the_tray_is_shown_alone(world):
    _move(world, "green_cylinder", (0.5, -0.4, 0.03))
    v = view_of(world, "green_cylinder")
    assert np.allclose(v["lookat_m"], (0.5, -0.4, 0.03)) and v["distance_m"] == pytest.approx(0.5)


def test_a_place_failure_gets_the_object_picture_a_close_failure_does_not(world, tmp_path):
    from grasp_pipeline.sim.scene_view import SceneView

    view = SceneView(world, 96, 72)
    try:
        rec = FailureSnapshotRecorder(tmp_path, view.render, ObjectView(world, view).render)
        verify = PickResult(anchor=[0.5, 0.0], success=True, placed=False, object="red_cube")
        close = PickResult(anchor=[0.5, 0.0], failed_stage="CLOSE", object="blue_cube")
        for row in (verify, close):
            rec.on_pick(PickEvent(0.0, row))
    finally:
        view.close()
    assert (tmp_path / "attempt_01_verify_object.png").exists()
    assert str(tmp_path / "attempt_01_verify_object.png") in verify.snapshots
    assert (tmp_path / "attempt_02_close_scene.png").exists()
    assert not (tmp_path / "attempt_02_close_object.png").exists()


def test_a_deferred_view_is_made_at_its_first_picture_and_draws_the_same(world, tmp_path):
    from grasp_pipeline.sim.scene_view import DeferredSceneView, SceneView

    args = {"width_px": 96, "height_px": 72}
    deferred, plain = DeferredSceneView(world, **args), SceneView(world, **args)
    try:
        rec = FailureSnapshotRecorder(tmp_path, deferred.render, ObjectView(world, deferred).render)
        assert not deferred.made  # nothing rendered, nothing made
        rec.on_pick(PickEvent(0.0, PickResult(anchor=[0.5, 0.0], failed_stage="CLOSE", object="blue_cube")))
        assert deferred.made and (tmp_path / "attempt_01_close_scene.png").exists()
        assert np.array_equal(deferred.render(), plain.render())
        view = view_of(world, "red_cube")
        assert np.array_equal(deferred.render_from(**view), plain.render_from(**view))
    finally:
        deferred.close()
        plain.close()
    assert not deferred.made
    deferred.close()  # (idempotent)
