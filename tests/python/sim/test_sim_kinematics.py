"""Our MJCF Panda against Franka's published kinematics, via the independent ``frankik``."""

from __future__ import annotations

import math

import frankik
import mujoco
import numpy as np

from grasp_pipeline.robot import description as rm

N_CONFIGS = 1000
TOL_M = 1e-6
TOL_RAD = 1e-6
# frankik.fk returns libfranka's O_T_EE: flange * Rz(-45 deg) * (0, 0, 0.1034), the Franka Hand's
# TCP; our flange is that times the inverse of this offset.
T_FLANGE_EE = np.eye(4)
T_FLANGE_EE[:3, :3] = [[math.cos(-math.pi / 4), -math.sin(-math.pi / 4), 0],
                       [math.sin(-math.pi / 4), math.cos(-math.pi / 4), 0],
                       [0, 0, 1]]
T_FLANGE_EE[2, 3] = 0.1034


def _rot_angle(Ra: np.ndarray, Rb: np.ndarray) -> float:
    """Angle of Ra^T Rb, accurate for tiny angles (from the skew part, not arccos)."""
    D = Ra.T @ Rb
    skew = 0.5 * np.array([D[2, 1] - D[1, 2], D[0, 2] - D[2, 0], D[1, 0] - D[0, 1]])
    return float(math.atan2(np.linalg.norm(skew), 0.5 * (np.trace(D) - 1.0)))


def test_flange_and_tcp_match_frankik_on_1000_random_configurations():
    model = rm.load_robot_model()
    data = mujoco.MjData(model)
    qi = rm.arm_qpos_indices(model)
    flange = model.body(rm.FLANGE_BODY).id
    tcp = model.site(rm.TCP_SITE).id
    rng = np.random.default_rng(12345)
    err_p = err_r = err_tcp = 0.0
    for _ in range(N_CONFIGS):
        q = rng.uniform(rm.PANDA_Q_MIN, rm.PANDA_Q_MAX)
        data.qpos[qi] = q
        mujoco.mj_kinematics(model, data)
        ee = frankik.fk(q)
        ref = ee @ np.linalg.inv(T_FLANGE_EE)
        err_p = max(err_p, float(np.linalg.norm(data.xpos[flange] - ref[:3, 3])))
        err_r = max(err_r, _rot_angle(data.xmat[flange].reshape(3, 3), ref[:3, :3]))
        err_tcp = max(err_tcp, float(np.linalg.norm(data.site_xpos[tcp] - ee[:3, 3])))
    assert err_p <= TOL_M, f"flange position error {err_p:.2e} m"
    assert err_r <= TOL_RAD, f"flange orientation error {err_r:.2e} rad"
    assert err_tcp <= TOL_M, f"TCP position error {err_tcp:.2e} m"


def test_limits_in_model_are_frankas():
    model = rm.load_robot_model()
    for i, name in enumerate(rm.PANDA_JOINT_NAMES):
        lo, hi = model.joint(name).range
        assert (lo, hi) == (rm.PANDA_Q_MIN[i], rm.PANDA_Q_MAX[i]), name
    for i, name in enumerate(rm.PANDA_ACTUATOR_NAMES):
        lo, hi = model.actuator(name).forcerange
        assert (lo, hi) == (-rm.PANDA_TAU_MAX[i], rm.PANDA_TAU_MAX[i]), name
    np.testing.assert_allclose(frankik.q_min_panda, rm.PANDA_Q_MIN)
    np.testing.assert_allclose(frankik.q_max_panda, rm.PANDA_Q_MAX)
    assert np.all((rm.READY_Q > rm.PANDA_Q_MIN) & (rm.READY_Q < rm.PANDA_Q_MAX))
    assert rm.PANDA_QD_MAX.shape == rm.PANDA_QDD_MAX.shape == (7,)


def test_the_hand_in_the_model_has_the_published_opening_and_force():
    model = rm.load_robot_model()
    grip = model.actuator(rm.GRIPPER_ACTUATOR)
    assert tuple(grip.ctrlrange) == (0.0, rm.GRIPPER_MAX_WIDTH_M)
    assert tuple(grip.forcerange) == (-rm.GRIPPER_MAX_FORCE_N, rm.GRIPPER_MAX_FORCE_N)
    for name in rm.FINGER_JOINT_NAMES:  # each finger travels half the gap
        assert tuple(model.joint(name).range) == (0.0, rm.GRIPPER_MAX_WIDTH_M / 2), name


def test_masses_are_the_identified_ones():
    model = rm.load_robot_model()
    link_masses = [model.body(f"panda_link{i}").mass[0] for i in range(8)]
    # Gaz et al. 2019 identified masses [kg]
    np.testing.assert_allclose(link_masses, [0.629769, 4.970684, 0.646926, 3.228604,
                                             3.587895, 1.225946, 1.666555, 0.735522])
    assert model.body(rm.HAND_BODY).mass[0] == 0.73


def test_flange_T_tcp_is_franka_hand_tcp():
    np.testing.assert_allclose(rm.flange_T_tcp(rm.load_robot_model()), T_FLANGE_EE, atol=1e-12)


def test_camera_mount_is_read_from_the_model_and_looks_along_the_approach():
    model = rm.load_robot_model()
    T = rm.flange_T_camera(model)
    assert abs(np.linalg.det(T[:3, :3]) - 1.0) < 1e-12
    # optical axis parallel to the TCP approach axis
    approach = rm.flange_T_tcp(model)[:3, 2]
    assert np.dot(T[:3, 2], approach) > 1 - 1e-12
    # change the mount in the model: the transform follows
    cam = model.camera(rm.CAMERA_NAME)
    cam.pos[2] += 0.01
    T2 = rm.flange_T_camera(model)
    assert abs(T2[2, 3] - T[2, 3] - 0.01) < 1e-12


def test_forward_kinematics_helper_matches_data():
    T = rm.forward_kinematics(rm.NEUTRAL_Q)
    ee = frankik.fk(rm.NEUTRAL_Q)
    np.testing.assert_allclose(T @ T_FLANGE_EE, ee, atol=1e-9)
