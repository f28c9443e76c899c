"""The simulated Franka Panda: names, limits and frames, read from our MJCF (``sim/panda.xml``).

This module is the single source of the robot's names and of the fixed transforms the rest of
the pipeline needs (the motion layer imports it for limits and FK of its collision shapes; the
orchestrator for the camera mount). Nothing here depends on a scene.

Frames (all 4x4 homogeneous transforms, metres, right-handed):

* **flange** — body ``panda_flange``: Franka's DH frame 8, 0.107 m past joint 7 along its axis.
* **TCP** — site ``tcp`` of body ``panda_hand``: the centre between the two fingertip pads,
  ``flange_T_tcp = [Rz(-45 deg), (0, 0, 0.1034)]``; its z axis is the approach direction (into
  the object), its y axis the closing direction of the fingers. This is also the end-effector
  frame that libfranka and the ``frankik`` library report for a Panda with the Franka Hand.
* **camera** — the optical frame of the eye-in-hand depth camera ``wrist_depth_camera``:
  z = optical axis (forward, along the approach), x = image right, y = image down (the
  OpenCV/ROS optical convention). MuJoCo's own camera frame looks along -z with +y up; it is
  converted here (a 180 deg turn about x), so every consumer sees the optical convention.

Limits (``PANDA_*``, ``GRIPPER_*``) are Franka's published figures (the robot's datasheet),
defined once in :mod:`.limits` and re-exported here.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import mujoco
import numpy as np

from ..assets import asset_path
# the published limits, defined once in .limits (re-exported: the robot's names in one place)
from .limits import (GRIPPER_MAX_FORCE_N, GRIPPER_MAX_WIDTH_M, PANDA_Q_MAX, PANDA_Q_MIN,  # noqa: F401
                     PANDA_QD_MAX, PANDA_QDD_MAX, PANDA_TAU_MAX)

#: MJCF file of the robot (arm + hand + camera), inside the package assets.
ROBOT_XML = "panda.xml"

PANDA_JOINT_NAMES: tuple[str, ...] = tuple(f"panda_joint{i}" for i in range(1, 8))
PANDA_ACTUATOR_NAMES: tuple[str, ...] = tuple(f"panda_act{i}" for i in range(1, 8))
FINGER_JOINT_NAMES: tuple[str, str] = ("panda_finger_joint1", "panda_finger_joint2")
GRIPPER_ACTUATOR = "gripper"
#: Fixed tendon whose length is the finger gap (pad to pad) in metres.
FINGER_GAP_TENDON = "finger_gap"
BASE_BODY = "panda_link0"
FLANGE_BODY = "panda_flange"
HAND_BODY = "panda_hand"
FINGER_BODIES: tuple[str, str] = ("panda_leftfinger", "panda_rightfinger")
FINGER_PAD_GEOMS: tuple[str, str] = ("leftfinger_pad", "rightfinger_pad")
TCP_SITE = "tcp"
CAMERA_NAME = "wrist_depth_camera"

#: Franka's common neutral pose (0, -pi/4, 0, -3pi/4, 0, pi/2, pi/4).
NEUTRAL_Q = np.array([0.0, -np.pi / 4, 0.0, -3 * np.pi / 4, 0.0, np.pi / 2, np.pi / 4])
NEUTRAL_Q.setflags(write=False)

#: The reference start ("ready") joints: from here the camera sees the three objects of the
#: reference scene (method.md §8) obliquely. Found with :func:`grasp_pipeline.sim.ik.solve_ik`
#: (seeded at :data:`NEUTRAL_Q`) for the camera at (0.30, -0.01, 0.62) m looking at the objects'
#: centroid (0.513, -0.013, 0.225) with image right along world -y: 0.45 m from the centroid,
#: optical axis 28 deg from vertical; every joint >= 33 % of its half-range from its limits.
READY_Q = np.array([-0.0083, -1.1587, -0.0186, -2.5716, -0.015, 1.9075, 0.7685])
READY_Q.setflags(write=False)

# Rotation taking MuJoCo's camera frame (x right, y up, looking along -z) to the optical
# frame (x right, y down, z forward): a 180 deg turn about x.
_MJCAM_T_OPTICAL = np.diag([1.0, -1.0, -1.0, 1.0])


@lru_cache(maxsize=1)
def _robot_model_cached() -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_path(str(asset_path(ROBOT_XML)))


def load_robot_model() -> mujoco.MjModel:
    """The robot alone (arm, hand, camera; no scene, no objects) as a fresh ``MjModel``.

    Use it for kinematics: ``qpos[:7]`` are the arm joints in :data:`PANDA_JOINT_NAMES` order,
    ``qpos[7:9]`` the two finger joints.
    """
    return mujoco.MjModel.from_xml_path(str(asset_path(ROBOT_XML)))


def _pose(pos: np.ndarray, quat_wxyz: np.ndarray) -> np.ndarray:
    T = np.eye(4)
    mat = np.empty(9)
    mujoco.mju_quat2Mat(mat, np.asarray(quat_wxyz, dtype=float))
    T[:3, :3] = mat.reshape(3, 3)
    T[:3, 3] = pos
    return T


def _body_T_in_flange(model: mujoco.MjModel, body_id: int) -> np.ndarray:
    """Pose of a body fixed to the flange (no joints in between), in the flange frame."""
    flange_id = model.body(FLANGE_BODY).id
    T = np.eye(4)
    b = body_id
    while b != flange_id:
        if model.body_jntnum[b] != 0:
            raise ValueError(f"body {model.body(b).name!r} is not rigidly attached to the flange")
        if b == 0:
            raise ValueError(f"body {model.body(body_id).name!r} is not below the flange")
        T = _pose(model.body_pos[b], model.body_quat[b]) @ T
        b = model.body_parentid[b]
    return T


def flange_T_camera(model: mujoco.MjModel) -> np.ndarray:
    """Camera optical frame (z forward, x right, y down) in the flange frame, from ``model``.

    Works on the robot-only model and on any scene model that contains the robot.
    """
    cam = model.camera(CAMERA_NAME)
    T_body_cam = _pose(cam.pos, cam.quat)
    return _body_T_in_flange(model, int(cam.bodyid[0])) @ T_body_cam @ _MJCAM_T_OPTICAL


def flange_T_tcp(model: mujoco.MjModel) -> np.ndarray:
    """TCP (centre between the fingertip pads; z = approach, y = closing) in the flange frame."""
    site = model.site(TCP_SITE)
    T_body_site = _pose(site.pos, site.quat)
    return _body_T_in_flange(model, int(site.bodyid[0])) @ T_body_site


def camera_fovy_deg(model: mujoco.MjModel) -> float:
    """Vertical field of view of the depth camera as stored in the model [deg]."""
    return float(model.cam_fovy[model.camera(CAMERA_NAME).id])


def flange_pose(model: mujoco.MjModel, data: mujoco.MjData) -> np.ndarray:
    """World pose of the flange for the kinematics already computed in ``data``."""
    bid = model.body(FLANGE_BODY).id
    T = np.eye(4)
    T[:3, :3] = data.xmat[bid].reshape(3, 3)
    T[:3, 3] = data.xpos[bid]
    return T


def arm_qpos_indices(model: mujoco.MjModel) -> np.ndarray:
    """Indices into ``qpos`` (and, the arm joints being hinges, ``qvel``) of the 7 arm joints."""
    return np.array([model.joint(n).qposadr[0] for n in PANDA_JOINT_NAMES], dtype=int)


def arm_dof_indices(model: mujoco.MjModel) -> np.ndarray:
    """Indices into ``qvel`` of the 7 arm joints."""
    return np.array([model.joint(n).dofadr[0] for n in PANDA_JOINT_NAMES], dtype=int)


def forward_kinematics(q: np.ndarray, model: mujoco.MjModel | None = None) -> np.ndarray:
    """World pose of the flange for arm joints ``q`` (7,), robot base at the origin.

    A convenience for tests and tools (it runs ``mj_kinematics`` on a private ``MjData``);
    hot loops should keep their own ``MjData``.
    """
    q = np.asarray(q, dtype=float).reshape(7)
    model = model if model is not None else _robot_model_cached()
    data = mujoco.MjData(model)
    data.qpos[arm_qpos_indices(model)] = q
    mujoco.mj_kinematics(model, data)
    return flange_pose(model, data)


@dataclass(frozen=True)
class HandClearances:
    """How the hand extends along the approach axis around the TCP [m], from the model.

    ``pad_below_tcp_m``: how far the finger pads reach past the TCP (towards the object);
    ``palm_above_tcp_m``: from the TCP back to the nearest face of the hand's other collision
    geoms (palm, camera housing) — an object taller than this above the TCP meets the palm;
    ``finger_thickness_m``: how far a finger reaches outwards from its pad's face (along the
    closing axis); ``finger_width_m``: its width across the closing axis."""

    pad_below_tcp_m: float
    palm_above_tcp_m: float
    finger_thickness_m: float
    finger_width_m: float


def _geom_reach_along_z(model: mujoco.MjModel, g: int, T_hand_body: np.ndarray) -> float:
    """The largest hand-frame z of geom ``g`` (a box or any geom's bounding box)."""
    T = T_hand_body @ _pose(model.geom_pos[g], model.geom_quat[g])
    half = model.geom_size[g] if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX else \
        np.full(3, model.geom_rbound[g])
    return float(T[2, 3] + np.abs(T[2, :3]) @ half)


def hand_clearances(model: mujoco.MjModel | None = None) -> HandClearances:
    """:class:`HandClearances` of the Franka Hand in ``model`` (default: our robot MJCF)."""
    model = model if model is not None else _robot_model_cached()
    hand = model.body(HAND_BODY).id
    tcp_z = float(model.site(TCP_SITE).pos[2])
    pad_z, palm_z = -np.inf, -np.inf
    out_y, half_x = _finger_footprint(model)
    for g in range(model.ngeom):
        b = int(model.geom_bodyid[g])
        if b != hand and int(model.body_parentid[b]) != hand:
            continue
        if model.geom_contype[g] == 0 and model.geom_conaffinity[g] == 0:
            continue
        T = np.eye(4) if b == hand else _pose(model.body_pos[b], model.body_quat[b])
        z = _geom_reach_along_z(model, g, T)
        if model.geom(g).name in FINGER_PAD_GEOMS:
            pad_z = max(pad_z, z)
        elif b == hand:
            palm_z = max(palm_z, z)
    return HandClearances(pad_below_tcp_m=pad_z - tcp_z, palm_above_tcp_m=tcp_z - palm_z,
                          finger_thickness_m=out_y, finger_width_m=2.0 * half_x)


def _finger_footprint(model: mujoco.MjModel) -> tuple[float, float]:
    """(outward reach from the pad face, half width) of the first finger's collision geoms, in
    its body frame (the finger opens along +y; the pad face is the pad's smallest y)."""
    body = model.body(FINGER_BODIES[0]).id
    pad = model.geom(FINGER_PAD_GEOMS[0])
    face_y = float(pad.pos[1] - pad.size[1])
    out_y, half_x = 0.0, 0.0
    for g in range(model.ngeom):
        if int(model.geom_bodyid[g]) != body or model.geom_type[g] != mujoco.mjtGeom.mjGEOM_BOX:
            continue
        R = _pose(model.geom_pos[g], model.geom_quat[g])[:3, :3]
        ext = np.abs(R) @ model.geom_size[g]
        out_y = max(out_y, float(model.geom_pos[g][1] + ext[1]) - face_y)
        half_x = max(half_x, float(abs(model.geom_pos[g][0]) + ext[0]))
    return out_y, half_x
