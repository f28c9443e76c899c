"""The camera frame contract: Frame.from_depth back-projects a depth image in metres, and
check_frame refuses, with one line that says what to fix, the frames a robot adapter gets
wrong — raw or float millimetre depth, a missing or non-rigid pose, missing intrinsics or those
of another resolution, a colour image of another size, points that disagree with the depth."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from grasp_pipeline.exceptions import CameraFrameError, RobotAdapterError
from grasp_pipeline.perception.synthetic import look_at
from grasp_pipeline.robot.frame import Frame
from grasp_pipeline.robot.frame_contract import check_frame

W, H = 64, 48
K = np.array([[50.0, 0.0, 31.5], [0.0, 50.0, 23.5], [0.0, 0.0, 1.0]])
T = look_at(np.array([0.3, 0.0, 0.6]), np.array([0.5, 0.0, 0.2]))


def _depth() -> np.ndarray:
    rng = np.random.default_rng(0)
    return (0.45 + 0.01 * rng.standard_normal((H, W))).astype(np.float32)


def _frame(**changes) -> Frame:
    return dataclasses.replace(Frame.from_depth(_depth(), K, T, 1.5), **changes)


def test_from_depth_back_projects_each_pixel_through_the_intrinsics_and_the_pose():
    depth = _depth()
    depth[0, 0], depth[1, 2] = 0.0, np.nan  # no return, as sensors report it (0) or NaN
    f = Frame.from_depth(depth, K, T, 1.5, index=3, backend="test")
    assert f.points_world.shape == (H * W, 3) and f.points_world.dtype == np.float32
    assert np.isnan(f.depth[0, 0]) and np.isnan(f.points_world[0]).all() and np.isnan(f.points_world[W + 2]).all()
    u, v = 40, 30
    z = float(depth[v, u])
    p_cam = np.array([(u - K[0, 2]) / K[0, 0] * z, (v - K[1, 2]) / K[1, 1] * z, z])
    np.testing.assert_allclose(f.points_world[v * W + u], T[:3, :3] @ p_cam + T[:3, 3], atol=1e-5)
    assert (f.time_s, f.index, f.backend, f.width, f.height) == (1.5, 3, "test", W, H)
    assert check_frame(f) is f


def _refused(fn) -> str:
    with pytest.raises(CameraFrameError) as info:
        fn()
    msg = str(info.value)
    assert "\n" not in msg and "docs/real_robot.md" in msg, msg
    assert isinstance(info.value, RobotAdapterError)
    return msg


@pytest.mark.parametrize("make, words", [
    (lambda: Frame.from_depth((_depth() * 1000).astype(np.uint16), K, T, 0.0), ["uint16", "millimetres", "depth scale"]),
    (lambda: Frame.from_depth(_depth() * 1000, K, T, 0.0), ["median of 450", "millimetres", "metres"]),
    (lambda: Frame.from_depth(_depth(), K, None, 0.0), ["pose", "missing", "hand-eye"]),
    (lambda: Frame.from_depth(_depth(), None, T, 0.0), ["no intrinsics", "get_intrinsics"]),
    (lambda: Frame.from_depth(_depth(), K, T, None), ["time_s"]),
    (lambda: Frame.from_depth(None, K, T, 0.0), ["no depth image"]),
])
def test_from_depth_refuses_what_a_camera_adapter_gets_wrong(make, words):
    msg = _refused(make)
    assert all(w in msg for w in words), msg


def _scaled_pose():
    bad = T.copy()
    bad[:3, :3] *= 1.2
    return bad


def _other_resolution():
    return np.array([[100.0, 0.0, 63.5], [0.0, 100.0, 47.5], [0.0, 0.0, 1.0]])  # for 128 x 96


@pytest.mark.parametrize("changes, words", [
    (lambda: {"depth": (_depth() * 1000).astype(np.uint16)}, ["uint16", "millimetres"]),
    (lambda: {"depth": _depth() * 1000}, ["millimetres"]),
    (lambda: {"depth": np.where(_depth() > 0.45, 0.0, _depth())}, ["<= 0", "NaN"]),
    (lambda: {"T_world_camera": None}, ["missing", "hand-eye"]),
    (lambda: {"T_world_camera": _scaled_pose()}, ["not a rigid transform"]),
    (lambda: {"T_world_camera": np.eye(3)}, ["4x4"]),
    (lambda: {"K": None}, ["no intrinsics"]),
    (lambda: {"K": _other_resolution()}, ["principal point", "another resolution"]),
    (lambda: {"K": K * np.array([[1, 1, 1], [1, -1, 1], [1, 1, 1]])}, ["fx, fy > 0"]),
    (lambda: {"rgb": np.zeros((H // 2, W // 2, 3), np.uint8)}, ["colour image", "aligned"]),
    (lambda: {"rgb": np.zeros((H, W, 3), np.float32)}, ["uint8"]),
    (lambda: {"points_world": np.zeros((10, 3), np.float32)}, ["organized"]),
    (lambda: {"points_world": Frame.from_depth(_depth(), K, np.eye(4), 0.0).points_world},
     ["disagree", "pose at capture"]),
    (lambda: {"time_s": float("nan")}, ["time_s"]),
])
def test_check_frame_refuses_a_frame_that_breaks_the_contract(changes, words):
    msg = _refused(lambda: check_frame(_frame(**changes())))
    assert all(w in msg for w in words), msg


def test_a_float32_pose_and_nan_holes_keep_the_contract():
    depth = _depth()
    depth[::3] = np.nan
    f = Frame.from_depth(depth, K, T.astype(np.float32), 2.0, rgb=np.zeros((H, W, 3), np.uint8))
    assert check_frame(f) is f
