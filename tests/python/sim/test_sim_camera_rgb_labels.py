"""Colour aligned with depth (``Frame.rgb``) and per-pixel object labels (evaluation only,
through ``ground_truth.frame_labels``), for the GL and the ray-cast backend."""

from __future__ import annotations

import dataclasses

import os

import numpy as np
import pytest

from grasp_pipeline.robot.frame import Frame
from grasp_pipeline.sim.config import CameraConfig, load_camera_config
from grasp_pipeline.sim.ground_truth import (NO_OBJECT, FrameLabelsError, enable_frame_labels,
                                             frame_labels, object_truths)
from grasp_pipeline.sim.gl_backend import GL_OFF_VALUES
from grasp_pipeline.sim.scenes import reference_scene

SMALL = {"width_px": 320, "height_px": 240}
BACKENDS = ["gl", "raycast"]


def _world(make_world, backend: str, **overrides):
    """A reference-scene world whose camera uses ``backend``: "gl" is whatever GL the test
    session chose (skipped where there is none), "raycast" is asked for explicitly."""
    values = dict(SMALL, **overrides)
    if backend == "raycast":
        values["backend"] = "raycast"
    world = make_world(reference_scene(), camera_config=load_camera_config(overrides=values))
    if backend == "gl" and world.camera.backend == "raycast":
        # only a user's explicit MUJOCO_GL=disable excuses the GL half; otherwise it must run
        if os.environ.get("MUJOCO_GL", "").strip().lower() not in GL_OFF_VALUES:
            pytest.fail("the GL camera fell back to ray casting although GL was not disabled")
        pytest.skip("MUJOCO_GL disables GL in this test session")
    return world


def _labelled(make_world, backend: str, **overrides):
    world = _world(make_world, backend, **overrides)
    enable_frame_labels(world)
    frame = world.capture()
    return world, frame, frame_labels(world, frame)


def _inside_object(points: np.ndarray, truth, tol: float) -> np.ndarray:
    """Per point, whether it lies within ``tol`` of the object's (box / cylinder) volume."""
    T = truth.T_world_object
    local = (points.astype(float) - T[:3, 3]) @ T[:3, :3]
    half = 0.5 * np.asarray(truth.size_m)
    if truth.kind == "cylinder":
        radial = np.linalg.norm(local[:, :2], axis=1) <= half[0] + tol
        return radial & (np.abs(local[:, 2]) <= half[2] + tol)
    return np.all(np.abs(local) <= half + tol, axis=1)


@pytest.mark.parametrize("backend", BACKENDS)
def test_rgb_is_aligned_with_depth(make_world, backend):
    world, f, labels = _labelled(make_world, backend)
    assert f.rgb is not None and f.rgb.shape == (f.height, f.width, 3) and f.rgb.dtype == np.uint8
    # the blue cube's pixels (found from the labels) are blue in the colour image
    blue = [o.name for o in world.scene.objects].index("blue_cube")
    px = f.rgb[labels == blue].astype(int)
    assert len(px) > 200
    r, g, b = px.T
    assert np.mean((b > r + 40) & (b > g + 40)) > 0.95
    # and the table around the objects is not blue
    table = f.rgb[(labels == NO_OBJECT) & np.isfinite(f.depth)].astype(int)
    assert np.mean(table[:, 2] > table[:, 0] + 40) < 0.01
    # labels exist only where the depth is valid
    assert np.all(labels[np.isnan(f.depth)] == NO_OBJECT)
    assert labels.shape == f.depth.shape and labels.dtype == np.int32


@pytest.mark.parametrize("backend", BACKENDS)
def test_rgb_off_gives_none_and_leaves_depth_unchanged(make_world, backend):
    on = _world(make_world, backend, add_noise=False)
    off = _world(make_world, backend, add_noise=False, rgb=False)
    f_on, f_off = on.capture(), off.capture()
    assert f_off.rgb is None and f_on.rgb is not None
    np.testing.assert_array_equal(f_on.depth, f_off.depth)
    enable_frame_labels(on)  # a labelled capture renders the same depth too
    np.testing.assert_array_equal(on.capture().depth, f_on.depth)


@pytest.mark.parametrize("backend", BACKENDS)
def test_every_object_is_labelled_where_it_really_is(make_world, backend):
    world, f, labels = _labelled(make_world, backend, add_noise=False)
    flat = labels.reshape(-1)
    truths = object_truths(world)
    assert set(np.unique(flat)) == {NO_OBJECT, 0, 1, 2}
    for i, truth in enumerate(truths):
        pts = f.points_world[flat == i]
        assert len(pts) > 200, truth.name
        assert np.all(np.isfinite(pts)), "labelled pixels are valid points"
        assert _inside_object(pts, truth, tol=0.003).mean() > 0.995, truth.name
        assert _inside_object(pts, truth, tol=0.006).all(), truth.name
    # and points labelled as no object are not on the objects' visible surfaces
    rest = f.points_world[(flat == NO_OBJECT) & f.valid_mask()]
    for truth in truths:
        assert _inside_object(rest, truth, tol=-0.003).sum() == 0, truth.name


def test_gl_and_raycast_labels_agree(make_world):
    _, fg, lg = _labelled(make_world, "gl", add_noise=False)
    _, fr, lr = _labelled(make_world, "raycast", add_noise=False)
    assert fg.backend != "raycast" and fr.backend == "raycast"
    both = np.isfinite(fg.depth) & np.isfinite(fr.depth)
    assert both.mean() > 0.9
    assert np.mean(lg[both] == lr[both]) >= 0.95
    on_objects = both & ((lg >= 0) | (lr >= 0))
    assert on_objects.sum() > 600 and np.mean(lg[on_objects] == lr[on_objects]) >= 0.95


def test_labels_refuse_an_old_frame(make_world):
    world = _world(make_world, "raycast", labels=True)  # on through the config
    first = world.capture()
    frame_labels(world, first)
    world.step(5)
    second = world.capture()
    with pytest.raises(FrameLabelsError, match="latest"):
        frame_labels(world, first)
    assert frame_labels(world, second).shape == second.depth.shape
    enable_frame_labels(world, False)
    third = world.capture()
    with pytest.raises(FrameLabelsError, match="without labels"):
        frame_labels(world, third)
    with pytest.raises(FrameLabelsError, match="latest"):
        frame_labels(world, second)


def test_labels_are_off_by_default_and_never_in_the_frame(make_world):
    assert CameraConfig().rgb is True and CameraConfig().labels is False
    world = _world(make_world, "raycast")
    f = world.capture()
    with pytest.raises(FrameLabelsError, match="without labels"):
        frame_labels(world, f)
    assert not any("label" in fld.name or "seg" in fld.name for fld in dataclasses.fields(Frame))
