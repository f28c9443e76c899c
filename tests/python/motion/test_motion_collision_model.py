"""Robot spheres, occupancy map and state validity."""

import mujoco
import numpy as np
import pytest

from grasp_pipeline.motion.exceptions import EnvironmentCloudError
from grasp_pipeline.motion.kinematics import ChainKinematics
from grasp_pipeline.motion.occupancy import OccupancyMap, OrientedBox
from grasp_pipeline.robot import description as rm


def test_chain_kinematics_equals_mujoco(planner, rng):
    m = planner.model
    d = mujoco.MjData(m)
    idx = rm.arm_qpos_indices(m)
    ck = ChainKinematics(m, idx)
    Q = rng.uniform(rm.PANDA_Q_MIN, rm.PANDA_Q_MAX, size=(10, 7))
    fixed = m.qpos0.copy()
    fixed[7:9] = 0.03
    R, p = ck.body_poses(Q, fixed)
    for k, q in enumerate(Q):
        d.qpos[:] = fixed
        d.qpos[idx] = q
        mujoco.mj_kinematics(m, d)
        assert np.allclose(d.xpos, p[k], atol=1e-12)
        assert np.allclose(d.xmat.reshape(-1, 3, 3), R[k], atol=1e-12)


def test_spheres_cover_collision_geoms(planner, rng):
    """Points sampled inside every collision geom lie inside one of its spheres."""
    m, rs = planner.model, planner.robot
    d = mujoco.MjData(m)
    d.qpos[:] = rs.fixed_qpos
    d.qpos[rs.arm_idx] = rm.READY_Q
    mujoco.mj_kinematics(m, d)
    C = rs.centres(np.asarray(rm.READY_Q)[None])[0]
    checked = 0
    for g in range(m.ngeom):
        if m.geom_contype[g] == 0 and m.geom_conaffinity[g] == 0:
            continue
        s, t = m.geom_size[g], m.geom_type[g]
        P = rng.uniform(-1.0, 1.0, (3000, 3))
        if t == mujoco.mjtGeom.mjGEOM_BOX:
            L = P * s
        elif t == mujoco.mjtGeom.mjGEOM_CAPSULE:
            L = np.c_[P[:, :2] * s[0], P[:, 2] * (s[1] + s[0])]
            zc = np.clip(L[:, 2], -s[1], s[1])
            L = L[np.linalg.norm(L - np.c_[0 * zc, 0 * zc, zc], axis=1) <= s[0]]
        elif t == mujoco.mjtGeom.mjGEOM_CYLINDER:
            L = np.c_[P[:, :2] * s[0], P[:, 2] * s[1]]
            L = L[np.hypot(L[:, 0], L[:, 1]) <= s[0]]
        else:
            continue
        W = L @ d.geom_xmat[g].reshape(3, 3).T + d.geom_xpos[g]
        sel = rs.spheres.geom == g
        gap = np.linalg.norm(W[:, None] - C[sel][None], axis=2) - rs.spheres.radius[sel][None]
        assert gap.min(axis=1).max() <= 1e-9, m.geom(g).name
        checked += 1
    assert checked >= 15


def test_ready_pose_valid_and_self_collision_detected(planner):
    planner.set_scene(np.zeros((0, 3)))
    v = planner.validator
    assert v.is_valid(rm.READY_Q), v.explain(rm.READY_Q)
    # elbow folded onto the base: joint 2 forward, joint 4 fully bent, joint 6 flipped
    q = np.array([0.0, 1.7, 0.0, -3.0, 0.0, 0.0, 0.0])
    assert not v.is_valid(q)
    assert "self-collision" in v.explain(q) or "floor" in v.explain(q)
    q_out = np.array(rm.READY_Q, dtype=float)
    q_out[3] = 0.1
    assert "joint 4" in v.explain(q_out)


def test_empty_cloud_is_free_space(planner):
    env = planner.set_scene(np.zeros((0, 3)))
    assert env.num_occupied == 0
    assert np.all(np.isinf(env.distance_m(np.array([[0.5, 0.0, 0.3]]))))
    path = planner.plan_path_to_joints(rm.READY_Q, rm.NEUTRAL_Q)
    assert path.method == "direct"


def test_distance_field_and_nan_points(table_cloud, rng):
    pts = table_cloud(rng, n=20000)
    pts = np.vstack([pts, [[np.nan, 0, 0], [np.inf, 1, 1]]])
    m = OccupancyMap.from_points(pts, 0.01, (-1, -1, -0.2), (1.5, 1, 1.5), pad_m=0.1,
                                 max_points=10**6, max_voxels=10**7)
    d = m.distance_m(np.array([[0.5, 0.0, 0.25], [0.5, 0.0, 0.2], [0.5, 0.0, 0.9]]))
    assert abs(d[0] - 0.05) <= m.inflation_m
    assert d[1] <= m.inflation_m
    assert np.isinf(d[2])  # farther than the padding from every point: outside the grid


def test_cloud_size_limits(planner):
    cfg = planner.config
    big = np.zeros((cfg.max_environment_points + 1, 3), dtype=np.float32)
    with pytest.raises(EnvironmentCloudError, match="over the limit"):
        planner.set_scene(big)
    del big
    # a cloud spanning the whole workspace at 1 cm exceeds the voxel limit with a clear message
    spread = np.array([cfg.workspace_min_m, cfg.workspace_max_m], dtype=float)
    with pytest.raises(EnvironmentCloudError, match="max_grid_voxels"):
        OccupancyMap.from_points(spread, 0.01, cfg.workspace_min_m, cfg.workspace_max_m, 0.1,
                                 cfg.max_environment_points, max_voxels=10**6)
    with pytest.raises(EnvironmentCloudError, match="shape"):
        planner.set_scene(np.zeros((10, 2)))


def test_large_cloud_is_voxelised(planner, rng):
    """Two million points of a table become a few thousand voxels."""
    pts = np.c_[rng.uniform(0.3, 0.9, 2_000_000), rng.uniform(-0.4, 0.4, 2_000_000),
                np.full(2_000_000, 0.2)].astype(np.float32)
    env = planner.set_scene(pts)
    assert env.num_occupied <= 60 * 80 * 2
    assert planner.validator.is_valid(rm.READY_Q)


def test_cleared_target_region(table_cloud, rng):
    pts = table_cloud(rng, n=30000)
    m = OccupancyMap.from_points(pts, 0.01, (-1, -1, -0.2), (1.5, 1, 1.5), pad_m=0.1,
                                 max_points=10**6, max_voxels=10**7)
    box = OrientedBox(np.array([0.5, 0.0, 0.225]), np.eye(3), np.array([0.05, 0.05, 0.05]))
    view = m.with_cleared_region(box.inflated(0.05))
    q = np.array([[0.5, 0.0, 0.21], [0.5, 0.2, 0.21]])
    d_full, d_clear = m.distance_m(q, cleared=True), view.distance_m(q, cleared=True)
    assert d_full[0] <= m.inflation_m and d_clear[0] >= 0.04   # table under the target ignored
    assert d_clear[1] <= m.inflation_m                         # elsewhere unchanged
    assert np.allclose(view.distance_m(q), d_full)             # without the flag: unchanged


def test_object_boxes_are_obstacles_but_target_is_not(planner):
    planner.set_scene(np.zeros((0, 3)))
    T = planner.ik.fk_tcp(rm.READY_Q)
    box = OrientedBox(T[:3, 3], np.eye(3), np.array([0.04, 0.04, 0.04]))
    planner.set_scene(np.zeros((0, 3)), [box])
    assert not planner.validator.is_valid(rm.READY_Q)
    assert "object box" in planner.validator.explain(rm.READY_Q)
    planner.set_target(0)
    assert planner.validator.is_valid(rm.READY_Q)
    planner.set_target(None)
