"""A render reused while nothing in view moves (``sim.still_scene``): the cache's rule, and
frames of a still scene equal, bit for bit, those of a camera that renders every frame."""

from __future__ import annotations

from dataclasses import replace

import mujoco
import numpy as np
import pytest

from grasp_pipeline.exceptions import ConfigError
from grasp_pipeline.sim.config import load_camera_config
from grasp_pipeline.sim.still_scene import CleanImages, StillSceneCache


def _images(tag: float) -> CleanImages:
    z = np.full((2, 3), tag, dtype=np.float32)
    return CleanImages(np.eye(4), z, np.zeros((2, 3), bool), None, None)


def test_the_cache_hands_out_the_kept_render_only_within_the_tolerance():
    cache = StillSceneCache(1e-6)
    key = np.zeros(12)
    assert cache.lookup(key) is None  # nothing kept yet
    kept = _images(0.5)
    cache.keep(key, kept)
    assert cache.lookup(key + 0.9e-6) is kept
    assert cache.lookup(key + np.r_[np.zeros(11), 2e-6]) is None  # one entry moved too far
    assert cache.lookup(np.zeros(15)) is None  # another scene (other geoms)
    assert (cache.renders, cache.reused) == (1, 1)
    cache.clear()
    assert cache.lookup(key) is None


def test_a_zero_tolerance_keeps_nothing():
    cache = StillSceneCache(0.0)
    cache.keep(np.zeros(3), _images(0.5))
    assert not cache.enabled and cache.lookup(np.zeros(3)) is None and cache.renders == 0


def test_a_negative_tolerance_is_refused():
    with pytest.raises(ConfigError, match="still_tolerance_m"):
        replace(load_camera_config(), still_tolerance_m=-1e-6).validate()


def _frames(world, n: int):
    return [world.capture() for _ in range(n)]


def _same(a, b) -> None:
    np.testing.assert_array_equal(a.depth, b.depth)  # NaN where NaN, equal elsewhere
    np.testing.assert_array_equal(a.points_world, b.points_world)
    np.testing.assert_array_equal(a.T_world_camera, b.T_world_camera)
    if a.rgb is not None or b.rgb is not None:
        np.testing.assert_array_equal(a.rgb, b.rgb)


def test_frames_of_a_still_scene_equal_those_of_a_render_per_frame(make_world):
    cfg = load_camera_config()
    every = make_world(camera_config=replace(cfg, still_tolerance_m=0.0))
    still = make_world(camera_config=replace(cfg, still_tolerance_m=1e-6))
    a, b = _frames(every, 3), _frames(still, 3)
    for fa, fb in zip(a, b):
        _same(fa, fb)
    assert not np.array_equal(a[0].depth, a[1].depth, equal_nan=True)  # each frame its own noise
    assert (still.camera._still.renders, still.camera._still.reused) == (1, 2)
    assert every.camera._still.renders == 0


def test_a_kept_render_is_not_shared_with_the_frames(make_world):
    world = make_world(camera_config=replace(load_camera_config(), add_noise=False))
    first = world.capture()
    first.depth[:] = 0.0
    if first.rgb is not None:
        first.rgb[:] = 0
    second = world.capture()
    assert world.camera._still.reused == 1
    assert np.nanmax(second.depth) > 0.0
    assert second.rgb is None or second.rgb.max() > 0


def test_a_move_beyond_the_tolerance_renders_anew(make_world):
    world = make_world()
    world.capture()
    world.data.qpos[0] += 1e-3  # the first arm joint: the camera moves about a millimetre
    mujoco.mj_forward(world.model, world.data)
    moved = world.capture()
    assert (world.camera._still.renders, world.camera._still.reused) == (2, 0)
    np.testing.assert_allclose(moved.T_world_camera, world.camera_pose())


def test_switching_labels_on_renders_anew(make_world):
    from grasp_pipeline.sim.ground_truth import enable_frame_labels, frame_labels

    world = make_world()
    world.capture()
    enable_frame_labels(world, True)
    frame = world.capture()  # the kept render has no labels: a new one
    assert frame_labels(world, frame).shape == frame.depth.shape
    assert (world.camera._still.renders, world.camera._still.reused) == (2, 0)
