"""Depth frames: geometry (plane and cube top at their heights), noise model, NaN handling,
pose at capture while moving, GL vs ray-cast agreement, backend logging."""

from __future__ import annotations

import logging
from dataclasses import replace

import numpy as np
import pytest

from grasp_pipeline import _core
from grasp_pipeline.exceptions import ConfigError
from grasp_pipeline.robot import description as rm
from grasp_pipeline.sim.camera import DepthCamera
from grasp_pipeline.sim.config import load_camera_config
from grasp_pipeline.sim.ground_truth import object_truths
from grasp_pipeline.sim.ik import solve_ik

TABLE_Z = 0.200


def _table_points(frame, world, margin=0.06):
    """Valid points over the table top, away from the objects and the table edges."""
    P = frame.valid_points().astype(float)
    sel = (P[:, 0] > 0.30) & (P[:, 0] < 0.80) & (np.abs(P[:, 1]) < 0.35) & (np.abs(P[:, 2] - TABLE_Z) < 0.03)
    for o in object_truths(world):
        sel &= np.linalg.norm(P[:, :2] - o.position_m[:2], axis=1) > margin
    return P[sel]


def _camera_above(world, xy, height_m):
    """Move the arm so the camera looks straight down from ``height_m`` above ``xy``."""
    T_cam = np.eye(4)
    T_cam[:3, :3] = np.diag([1.0, -1.0, -1.0]) @ np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1.0]])
    T_cam[:3, 3] = [xy[0], xy[1], height_m]
    q, ok = solve_ik(T_cam, world.q, rm.flange_T_camera(world.model), rm.load_robot_model())
    assert ok
    return q


def test_frame_format(make_world):
    world = make_world()
    f = world.capture()
    cfg = world.camera_config
    assert f.points_world.shape == (cfg.width_px * cfg.height_px, 3)
    assert f.points_world.dtype == np.float32 and f.depth.dtype == np.float32
    assert f.depth.shape == (cfg.height_px, cfg.width_px)
    # organized: NaN rows exactly where the depth is NaN
    np.testing.assert_array_equal(np.isnan(f.points_world[:, 0]), np.isnan(f.depth.reshape(-1)))
    assert 0.5 < f.valid_mask().mean() < 1.0
    assert np.nanmin(f.depth) >= cfg.min_range_m - 0.02
    assert f.time_s == world.time_s
    assert f.backend in ("egl", "osmesa", "gl", "raycast")
    # intrinsics: vertical FOV 58 deg
    fov = 2 * np.degrees(np.arctan(0.5 * cfg.height_px / f.K[1, 1]))
    assert fov == pytest.approx(58.0)
    np.testing.assert_allclose(f.T_world_camera, world.flange_pose() @ rm.flange_T_camera(world.model),
                               atol=1e-9)


def test_table_plane_reprojects_to_its_height_within_noise(make_world):
    world = make_world()
    f = world.capture()
    P = _table_points(f, world)
    assert len(P) > 50000
    res = P[:, 2] - TABLE_Z
    assert abs(np.median(res)) < 0.0005
    # noise model: sigma(z) = 2 mm (z / 0.4)^2, z = depth along the optical axis
    z_cam = (P - f.T_world_camera[:3, 3]) @ f.T_world_camera[:3, 2]
    sigma = 0.002 * (z_cam / 0.4) ** 2
    # the noise is along the ray; its vertical share is |ray_z| / ray_z_cam... use normalised residuals
    ray = P - f.T_world_camera[:3, 3]
    vert = np.abs(ray[:, 2]) / z_cam          # d(point z) / d(depth)
    normalised = res / (sigma * vert)
    assert np.std(normalised) == pytest.approx(1.0, abs=0.1)


def test_noise_free_plane_is_exact(make_world):
    world = make_world(camera_config=load_camera_config(overrides={"add_noise": False}))
    P = _table_points(world.capture(), world)
    assert np.abs(P[:, 2] - TABLE_Z).max() < 0.0005


def test_cube_top_face_at_its_height(make_world, motion):
    world = make_world()
    cube = next(o for o in object_truths(world) if o.name == "blue_cube")
    top = cube.top_z_m
    motion.move(world, _camera_above(world, cube.position_m[:2] + [0.0, 0.03], top + 0.39), 2.0)
    f = world.capture()
    P = f.valid_points().astype(float)
    inside = np.abs((P[:, :2] - cube.position_m[:2]) @ cube.T_world_object[:2, :2]) < 0.02
    on_top = np.all(inside, axis=1) & (P[:, 2] > top - 0.015)
    assert on_top.sum() > 1000
    assert np.median(P[on_top, 2]) == pytest.approx(top, abs=0.0007)


def test_pose_in_frame_is_the_pose_at_capture_while_moving(make_world, motion):
    world = make_world()
    q_goal = rm.READY_Q + np.array([0.4, 0.15, 0.0, 0.2, 0.0, -0.1, 0.3])
    t, q, qd = motion.minjerk(world.q, q_goal, 1.0)
    world.follow_trajectory(t, q, qd)
    world.run_until(world.time_s + 0.5)
    assert np.linalg.norm(world.qd) > 0.3, "arm should be moving fast"
    f = world.capture()
    expected = rm.forward_kinematics(world.q) @ rm.flange_T_camera(world.model)
    np.testing.assert_allclose(f.T_world_camera, expected, atol=1e-9)
    assert f.time_s == world.time_s
    stored = f.T_world_camera.copy()
    world.step(20)
    assert np.linalg.norm(world.camera_pose()[:3, 3] - stored[:3, 3]) > 0.005
    np.testing.assert_array_equal(f.T_world_camera, stored)
    # and the image belongs to that pose: the table still lands at its height
    P = _table_points(f, world, margin=0.08)
    assert abs(np.median(P[:, 2]) - TABLE_Z) < 0.001


def test_frames_come_at_30_hz_of_simulated_time(make_world):
    world = make_world(camera_config=load_camera_config(overrides={"width_px": 160, "height_px": 120}))
    frames = []
    world.run_until(world.time_s + 1.0, on_frame=frames.append)
    times = np.array([f.time_s for f in frames])
    assert len(frames) in (30, 31)
    assert np.allclose(np.diff(times), 1 / 30, atol=world.timestep_s)
    assert [f.index for f in frames] == list(range(len(frames)))


def test_raycast_fallback_agrees_with_gl(make_world):
    cfg = {"add_noise": False, "width_px": 320, "height_px": 240}
    gl = make_world(camera_config=load_camera_config(overrides=dict(cfg, backend="gl")))
    rc = make_world(camera_config=load_camera_config(overrides=dict(cfg, backend="raycast")))
    fg, fr = gl.capture(), rc.capture()
    assert fr.backend == "raycast" and fg.backend != "raycast"
    assert fr.points_world.shape == fg.points_world.shape and fr.points_world.dtype == np.float32
    both = np.isfinite(fg.depth) & np.isfinite(fr.depth)
    assert both.mean() > 0.95
    assert (np.isfinite(fg.depth) != np.isfinite(fr.depth)).mean() < 0.01
    diff = np.abs(fg.depth[both] - fr.depth[both])
    assert np.median(diff) < 1e-4 and np.quantile(diff, 0.99) < 2e-3


def test_backend_is_logged(make_world, caplog):
    with caplog.at_level(logging.INFO, logger="grasp_pipeline.sim.camera"):
        make_world(camera_config=load_camera_config(overrides={"width_px": 64, "height_px": 48}))
    assert any("depth camera backend" in r.getMessage() for r in caplog.records)


def test_grazing_and_out_of_range_pixels_are_nan(make_world):
    near = make_world(camera_config=load_camera_config(overrides={"max_range_m": 0.5}))
    f = near.capture()
    assert np.nanmax(f.depth) <= 0.5 + 0.02
    strict = make_world(camera_config=load_camera_config(overrides={"grazing_max_deg": 30.0}))
    loose = make_world(camera_config=load_camera_config(overrides={"grazing_max_deg": 89.0}))
    # the camera looks 28 deg off vertical at the table: 30 deg keeps it, object sides go
    assert np.isfinite(strict.capture().depth).mean() < np.isfinite(loose.capture().depth).mean()


@pytest.mark.parametrize("bad", [{"vfov_deg": 0.0}, {"min_range_m": 2.0, "max_range_m": 1.0},
                                 {"backend": "vulkan"}, {"rate_hz": 0}])
def test_bad_camera_config_is_refused(bad):
    with pytest.raises(ConfigError):
        load_camera_config(overrides=bad)


def test_without_gl_frames_are_ray_cast_and_logged():
    """A process where GL is unavailable (MUJOCO_GL=disable) still gets frames, ray-cast."""
    import os
    import subprocess
    import sys

    code = (
        "import logging, sys\n"
        "logging.basicConfig(level=logging.INFO, stream=sys.stdout)\n"
        "from grasp_pipeline.sim.world import SimWorld\n"
        "from grasp_pipeline.sim.config import load_camera_config\n"
        "w = SimWorld(camera_config=load_camera_config(overrides={'width_px': 64, 'height_px': 48}))\n"
        "f = w.capture()\n"
        "print('FRAME', f.backend, f.points_world.shape, f.points_world.dtype)\n"
    )
    env = dict(os.environ, MUJOCO_GL="disable")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                         timeout=120, check=True).stdout
    assert "depth camera backend: raycast" in out
    assert "FRAME raycast (3072, 3) float32" in out


def _reference_frame(cam, z, T):
    """A frame's depth and points from clean depth ``z`` as the camera computes them, written
    plainly (np.where, one expression each)."""
    cfg, noise = cam.config, cam.depth_noise
    invalid = ~((z >= cfg.min_range_m) & (z <= cfg.max_range_m))
    z = np.where(invalid, np.float32(np.nan), z)
    gu, gv = np.zeros_like(z), np.zeros_like(z)
    with np.errstate(invalid="ignore", over="ignore"):
        for g, d in ((gu[:, 1:-1], np.diff(z, axis=1).T), (gv[1:-1].T, np.diff(z, axis=0))):
            g.T[...] = np.where(np.abs(d[1:]) <= np.abs(d[:-1]), d[1:], d[:-1])
        gu, gv = gu * cam._fx, gv * cam._fy
        nz = gu * cam._x + gv * cam._y + z
        invalid |= z * z < (cam._cos_grazing**2) * (gu * gu + gv * gv + nz * nz) * cam._ray_norm2
        sigma = np.float32(noise.depth_noise_sigma_m) * (
            z / np.float32(noise.depth_noise_ref_range_m)) ** np.float32(noise.depth_noise_exponent)
        draws = np.empty(z.shape, dtype=np.float32)
        _core.fill_standard_normal(draws, int(cam._rng.bit_generator.random_raw()))
        z = z + sigma * draws
    z[invalid] = np.nan
    R = T[:3, :3].astype(np.float32)
    pts = [z * (R[i, 0] * cam._x + R[i, 1] * cam._y + R[i, 2]) + np.float32(T[i, 3]) for i in range(3)]
    return z, np.stack(pts, axis=-1).reshape(-1, 3)


def test_frames_are_bit_identical_to_the_plain_computation(make_world):
    """Two cameras of the same seed and clean depth (steps, slopes, NaN, out of range): the
    capture's depth and points equal the plain computation's, frame after frame (each frame
    rendered: the clean depth is swapped in per frame while the scene stands still)."""
    world = make_world(camera_config=replace(load_camera_config(), still_tolerance_m=0.0))
    cam, T = world.camera, world.camera.pose()
    ref = DepthCamera(world.model, world.data, cam.config, raycast_threads=1, depth_noise=cam.depth_noise)
    rng = np.random.default_rng(1)
    try:
        for _ in range(3):
            h, w = cam.config.height_px, cam.config.width_px
            z = (0.3 + 0.2 * np.add.outer(np.arange(h) / h, (np.arange(w) / w) ** 2)).astype(np.float32)
            z[rng.random(z.shape) < 0.05] += np.float32(0.05)  # steps: grazing pixels
            z[rng.random(z.shape) < 0.02] = np.nan
            z[rng.random(z.shape) < 0.02] = np.float32(5.0)
            cam._clean_images = lambda T, z=z: (z.copy(), None, None)
            frame = cam.capture()
            depth, points = _reference_frame(ref, z, T)
            assert frame.depth.tobytes() == depth.tobytes()
            assert frame.points_world.tobytes() == points.tobytes()
    finally:
        ref.close()
