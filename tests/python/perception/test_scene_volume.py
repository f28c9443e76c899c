"""The scene volume wrapper (perception/scene_volume.py) on synthetic depth images."""

import pickle
from types import SimpleNamespace

import numpy as np
import pytest

from grasp_pipeline.exceptions import ConfigError
from grasp_pipeline.perception.scene_volume import FREE, OCCUPIED, OUTSIDE, UNKNOWN, SceneVolume
from grasp_pipeline.perception.volume_config import VolumeConfig

from .synthetic_depth import K, look_at, render

BOX = ((0.45, -0.05, 0.20), (0.55, 0.05, 0.30))  # 10 cm cube on the table (z = 0.2)
TOP_VIEW = look_at((0.5, 0.0, 0.65), (0.5, 0.0, 0.2), up=(1.0, 0.0, 0.0))


def _frame(T, boxes=(BOX,), table_z=0.2):
    return SimpleNamespace(depth=render(T, boxes, table_z), K=K, T_world_camera=T)


def test_a_top_view_carves_above_and_beside_and_leaves_the_inside_unknown():
    vol = SceneVolume()
    out = vol.integrate(*_args(_frame(TOP_VIEW)))
    assert out.voxels_free > 0 and out.voxels_occupied > 0
    states = vol.classify(np.array([
        [0.5, 0.0, 0.35],     # above the cube
        [0.5, 0.0, 0.3025],   # its top
        [0.5, 0.0, 0.24],     # inside
        [0.65, 0.0, 0.26],    # beside it
        [0.65, 0.0, 0.2025],  # the table
        [0.65, 0.0, 0.185],   # under the table
        [2.0, 0.0, 0.3],      # outside the box
    ]))
    assert states.tolist() == [FREE, OCCUPIED, UNKNOWN, FREE, OCCUPIED, UNKNOWN, OUTSIDE]
    tops = vol.occupied_centres((0.44, -0.06, 0.21), (0.56, 0.06, 0.35))
    assert len(tops) > 0 and np.all(tops[:, 2] > 0.28)


def test_a_depth_image_that_crossed_a_pickle_integrates_as_the_original():
    frame = _frame(TOP_VIEW)
    depth = frame.depth.astype(np.float32)
    moved = pickle.loads(pickle.dumps(depth))  # as a process pool or Ray hands it over
    assert moved.dtype is not np.dtype(np.float32)
    a, b = SceneVolume(), SceneVolume()
    out_a = a.integrate(depth, frame.K, frame.T_world_camera)
    out_b = b.integrate(moved, frame.K, frame.T_world_camera)
    assert (out_a.voxels_free, out_a.voxels_occupied) == (out_b.voxels_free, out_b.voxels_occupied)
    assert out_a.voxels_occupied > 0


def _args(frame):
    return frame.depth, frame.K, frame.T_world_camera


def test_a_static_camera_is_integrated_every_nth_frame_and_a_moved_one_at_once():
    vol = SceneVolume(VolumeConfig(volume_integrate_every_frames=5))
    frame = _frame(TOP_VIEW)
    done = [vol.offer(frame) is not None for _ in range(11)]
    assert done == [True, False, False, False, False, True, False, False, False, False, True]
    moved = _frame(look_at((0.5, 0.02, 0.65), (0.5, 0.0, 0.2), up=(1.0, 0.0, 0.0)))
    assert vol.offer(moved) is not None
    assert vol.stats.frames_offered == 12 and vol.stats.frames_integrated == 4
    assert vol.stats.integrate_cpu_s > 0


def test_forgetting_after_an_attempt_follows_the_policy():
    centre, R, ext = (0.5, 0.0, 0.25), np.eye(3), (0.1, 0.1, 0.1)
    far = np.array([[0.75, 0.2, 0.25]])
    for policy, near_state, far_state in (("target", UNKNOWN, FREE), ("all", UNKNOWN, UNKNOWN),
                                          ("none", FREE, FREE)):
        vol = SceneVolume(VolumeConfig(volume_forget=policy))
        vol.integrate(*_args(_frame(look_at((0.5, 0.0, 0.75), (0.6, 0.1, 0.2), up=(1.0, 0.0, 0.0)))))
        near = np.array([[0.5, 0.0, 0.36]])  # above the cube: seen free
        assert vol.classify(near)[0] == FREE and vol.classify(far)[0] == FREE
        vol.forget_after_attempt(centre, R, ext)
        assert (vol.classify(near)[0], vol.classify(far)[0]) == (near_state, far_state), policy


def test_an_object_that_left_is_carved_away_by_later_frames():
    vol = SceneVolume(VolumeConfig(volume_integrate_every_frames=1))
    with_cube, without = _frame(TOP_VIEW), _frame(TOP_VIEW, boxes=())
    top = np.array([[0.5, 0.0, 0.3025]])
    for _ in range(10):
        vol.offer(with_cube)
    assert vol.classify(top)[0] == OCCUPIED
    frames = 0
    while vol.classify(top)[0] == OCCUPIED and frames < 20:
        vol.offer(without)
        frames += 1
    assert vol.classify(top)[0] == FREE and frames <= 9  # clamp 3.5 / 0.4 per frame


def test_visibility_needs_a_camera_model_and_stops_at_the_cube():
    vol = SceneVolume()
    behind = np.array([[0.60, 0.0, 0.25]])
    side = look_at((0.15, 0.0, 0.25), (0.5, 0.0, 0.25))
    with pytest.raises(ValueError, match="no camera model"):
        vol.visible(behind, side, 0.1)
    vol.integrate(*_args(_frame(side)))
    assert not vol.visible(behind, side, 0.1)[0]
    assert vol.visible(behind, look_at((0.85, 0.0, 0.25), (0.5, 0.0, 0.25)), 0.1)[0]


@pytest.mark.parametrize("args, error, match", [
    ((np.zeros((4, 4), np.int16), K, np.eye(4)), TypeError, "dtype float32"),
    ((np.zeros(4, np.float32), K, np.eye(4)), ValueError, "shape"),
    ((np.zeros((4, 4), np.float32), np.eye(2), np.eye(4)), ValueError, "K"),
    ((np.zeros((4, 4), np.float32), K, np.full((4, 4), np.nan)), ValueError, "finite"),
    ((np.zeros((4, 4), np.float32), K, np.diag([1.0, 1.0, 2.0, 1.0])), ValueError, "rotation"),
])
def test_bad_frames_raise_clear_errors_and_change_nothing(args, error, match):
    vol = SceneVolume()
    with pytest.raises(error, match=match):
        vol.integrate(*args)
    assert vol.stats.frames_integrated == 0 and vol.core.frames_integrated == 0


@pytest.mark.parametrize("override, match", [
    ({"volume_voxel_m": 0.0}, "volume_voxel_m"),
    ({"volume_box_min_m": (0.0, 0.0)}, "volume_box_min_m"),
    ({"volume_box_max_m": (0.25, -0.40, 0.18)}, "volume_box_max_m"),
    ({"volume_truncation_m": 0.001}, "volume_truncation_m"),
    ({"volume_forget": "sometimes"}, "volume_forget"),
    ({"side_view_elevations_deg": (95.0,)}, "side_view_elevations_deg"),
])
def test_bad_configs_name_the_parameter(override, match):
    with pytest.raises(ConfigError, match=match):
        VolumeConfig(**override)


def test_the_default_box_is_the_table_top_in_5_mm_voxels():
    vol = SceneVolume()
    assert vol.core.shape == [120, 160, 64]
    assert vol.memory_bytes == 120 * 160 * 64 * 4
