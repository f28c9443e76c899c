"""The ray-cast depth backend's fast path (per-tile frustum culling into small private models,
1-2 threads) against a straightforward reference ray cast: one ``mj_multiRay`` over all visible
geoms of the scene model on one thread. Depths must be identical, and culling must never drop
a geom that the reference ray cast hits."""

from __future__ import annotations

import dataclasses

import mujoco
import numpy as np
import pytest

from grasp_pipeline.robot.description import (CAMERA_NAME, PANDA_Q_MAX, PANDA_Q_MIN,
                                              arm_qpos_indices)
from grasp_pipeline.sim.camera import (RAYCAST_MAX_THREADS, VISIBLE_GEOM_GROUPS, DepthCamera,
                                       default_raycast_threads)
from grasp_pipeline.sim.config import load_camera_config
from grasp_pipeline.sim.world import SimWorld


def _config():
    return dataclasses.replace(load_camera_config(), add_noise=False, backend="raycast")


def _reference(cam: DepthCamera, T: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Clean depth (H, W) float32 and hit geom per pixel (-1: none), all geoms, one thread."""
    cfg = cam.config
    h, w = cfg.height_px, cfg.width_px
    vec = np.empty((h, w, 3))
    for i, d in enumerate(cam._world_directions(T[:3, :3])):
        vec[..., i] = d / cam._ray_norm
    geomid = np.empty(h * w, dtype=np.int32)
    dist = np.empty(h * w)
    mujoco.mj_multiRay(cam.model, cam.data, T[:3, 3].copy(), vec.reshape(-1), VISIBLE_GEOM_GROUPS,
                       1, -1, geomid, dist, None, h * w,
                       float(cfg.max_range_m) * float(cam._ray_norm.max()))
    dist[geomid < 0] = np.inf
    return (dist.reshape(h, w) / cam._ray_norm).astype(np.float32), geomid.reshape(h, w)


def _objects(model: mujoco.MjModel) -> list[tuple[int, int]]:
    """(qpos address, geom) of each free-floating object, in joint order."""
    return [(int(model.jnt_qposadr[j]), int(model.body_geomadr[model.jnt_bodyid[j]]))
            for j in range(model.njnt) if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE]


def _poses():
    """(name, arm q offset seed or None, object placement) of the tested states."""
    return [("start", None, None), ("random1", 1, None), ("random2", 2, None),
            ("random3", 3, None), ("objects_at_camera", None, "near"),
            ("objects_at_frustum_edges", None, "edges")]


def _set_state(world: SimWorld, seed, objects) -> None:
    """From the initial state: arm joints offset by a seeded random amount, objects moved."""
    m, d = world.model, world.data
    d.qpos[:] = world.initial_qpos
    if seed is not None:
        qi = arm_qpos_indices(m)
        rng = np.random.default_rng(seed)
        d.qpos[qi] = np.clip(d.qpos[qi] + rng.uniform(-0.6, 0.6, 7), PANDA_Q_MIN, PANDA_Q_MAX)
    if objects is not None:
        mujoco.mj_kinematics(m, d)
        mujoco.mj_camlight(m, d)
        cam = m.camera(CAMERA_NAME).id
        o = d.cam_xpos[cam]
        R = d.cam_xmat[cam].reshape(3, 3)  # MuJoCo camera frame: looks along -z, y up
        fwd, right, up = -R[:, 2], R[:, 0], R[:, 1]
        if objects == "near":  # in front of the lens, between and beside the fingers
            offsets = [0.05 * fwd + 0.02 * right, 0.09 * fwd - 0.03 * up, 0.15 * fwd + 0.04 * up]
        else:  # centred on the right and the top image borders, one just behind the camera
            cfg = world.camera_config
            tan_v = np.tan(np.radians(cfg.vfov_deg) / 2)
            tan_h = tan_v * cfg.width_px / cfg.height_px
            offsets = [0.2 * (fwd + tan_h * right), 0.25 * (fwd + tan_v * up),
                       -0.05 * fwd + 0.04 * right]
        for (adr, _), off in zip(_objects(m), offsets):
            d.qpos[adr:adr + 3] = o + off
    mujoco.mj_kinematics(m, d)
    mujoco.mj_camlight(m, d)


@pytest.fixture(scope="module")
def world():
    w = SimWorld(camera_config=_config())
    w.initial_qpos = w.data.qpos.copy()
    yield w
    w.close()


@pytest.mark.parametrize("name,seed,objects", _poses())
def test_fast_raycast_equals_reference(world, name, seed, objects):
    _set_state(world, seed, objects)
    cam = world.camera
    assert cam.backend == "raycast"
    assert cam._raycast_candidates() is not None, "default scene must take the fast path"
    T = cam.pose()
    z_ref, hit = _reference(cam, T)
    if objects == "near":
        obj_geoms = [g for _, g in _objects(world.model)]
        assert np.isin(hit, obj_geoms).mean() > 0.2, "objects should fill much of the image"
        assert np.nanmin(np.where(np.isfinite(z_ref), z_ref, np.nan)) < 0.06
    if objects == "edges":  # cut by the right and the top image borders
        (_, first), (_, second) = _objects(world.model)[:2]
        assert first in hit[:, -1] and second in hit[0]
    for threads in (1, 2):
        cam.raycast_threads = threads
        z = cam._clean_depth_raycast(T)
        assert z.dtype == np.float32 and z.shape == z_ref.shape
        np.testing.assert_array_equal(np.isfinite(z), np.isfinite(z_ref))
        fin = np.isfinite(z_ref)
        assert np.abs(z[fin].astype(float) - z_ref[fin]).max(initial=0.0) < 1e-6
        assert np.array_equal(z, z_ref), f"{name}, {threads} threads: not bit-identical"


@pytest.mark.parametrize("name,seed,objects", _poses())
def test_culling_never_drops_a_hit(world, name, seed, objects):
    _set_state(world, seed, objects)
    cam = world.camera
    T = cam.pose()
    _, hit = _reference(cam, T)
    tile_geoms = cam._tile_geoms(T, cam._raycast_candidates())
    assert len(tile_geoms) == len(cam._tiles)
    covered = np.zeros(hit.shape, dtype=int)
    culled_any = False
    for (r0, r1, c0, c1), geoms in zip(cam._tiles, tile_geoms):
        covered[r0:r1, c0:c1] += 1
        seen = np.unique(hit[r0:r1, c0:c1])
        seen = seen[seen >= 0]
        dropped = np.setdiff1d(seen, geoms)
        assert dropped.size == 0, (f"{name}: tile {(r0, r1, c0, c1)} hit geoms "
                                   f"{[world.model.geom(g).name for g in dropped]} that were culled")
        culled_any |= len(geoms) < len(cam._raycast_candidates())
    np.testing.assert_array_equal(covered, 1)  # the tiles tile the image
    assert culled_any


def test_frames_equal_reference_frames(world):
    """Whole frames (validity masks, grazing filter, points) from the fast and the plain path."""
    _set_state(world, 5, None)
    cam = world.camera
    cam.raycast_threads = 2
    fast = world.capture()
    plain = cam._clean_depth_raycast_plain
    cam._clean_depth_raycast = plain  # instance attribute shadows the method
    try:
        ref = world.capture()
    finally:
        del cam._clean_depth_raycast
    np.testing.assert_array_equal(fast.depth, ref.depth)
    np.testing.assert_array_equal(fast.points_world, ref.points_world)
    assert 0.3 < fast.valid_mask().mean() <= 1.0


def test_thread_pool_is_owned_and_closed():
    assert 1 <= default_raycast_threads() <= RAYCAST_MAX_THREADS == 2
    w = SimWorld(camera_config=_config())
    cam = w.camera
    cam.raycast_threads = 2
    f1 = w.capture()
    assert cam._pool is not None
    w.close()
    assert cam._pool is None and not cam._ray_scenes
    f2 = w.capture()  # still usable after close (the pool is recreated on demand)
    np.testing.assert_array_equal(f1.depth, f2.depth)
    w.close()
