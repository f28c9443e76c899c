"""The hand as the grasp checks see it: boxes for contact with the target, the planner's
spheres for everything else, both in the TCP frame.

TCP frame (``grasp_pipeline.robot.description``): x across the closing axis, y the closing
axis, z the approach (into the object); the TCP is the centre between the finger pads.
Read from the robot model once (never hard-coded): every collision geom of the hand and its
fingers as an oriented box in the TCP frame (a cylinder by its bounding box), at a zero and
at the full opening (the fingers slide along y), and the planner's covering spheres
(:func:`grasp_pipeline.motion.robot_spheres.hand_spheres_in_tcp`).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import mujoco
import numpy as np

from ...motion.robot_spheres import hand_spheres_in_tcp
from ...robot import description as rm


@dataclass(frozen=True)
class HandBoxes:
    """The hand's collision geoms as boxes in the TCP frame: ``centre_closed`` (B, 3) at a
    zero opening, ``per_opening`` (B, 3) their shift per metre of opening, ``R`` (B, 3, 3)
    their axes, ``half`` (B, 3) half extents, ``names`` and ``finger`` (B,) True for the
    fingers' geoms (pads included), ``pad`` (B,) True for the pads."""

    centre_closed: np.ndarray
    per_opening: np.ndarray
    R: np.ndarray
    half: np.ndarray
    names: tuple
    finger: np.ndarray
    pad: np.ndarray

    def centres(self, opening_m: float) -> np.ndarray:
        return self.centre_closed + float(opening_m) * self.per_opening

    def corners(self, opening_m: float, select=None) -> np.ndarray:
        """(B·8, 3) box corners in the TCP frame at ``opening_m`` (``select``: a mask of boxes)."""
        sel = np.ones(len(self.half), bool) if select is None else np.asarray(select, bool)
        signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], float)
        c, R, h = self.centres(opening_m)[sel], self.R[sel], self.half[sel]
        local = signs[None, :, :] * h[:, None, :]
        return (c[:, None, :] + np.einsum("bij,bkj->bki", R, local)).reshape(-1, 3)


@dataclass(frozen=True)
class HandSpheres:
    """The planner's spheres of the hand and fingers in the TCP frame: ``centres_closed`` at a
    zero opening, ``per_opening`` (S, 3) their shift per metre of opening, ``radii`` (S,)."""

    centres_closed: np.ndarray
    per_opening: np.ndarray
    radii: np.ndarray

    def at(self, opening_m: float) -> np.ndarray:
        return self.centres_closed + float(opening_m) * self.per_opening


@dataclass(frozen=True)
class HandModel:
    """Everything the grasp checks need to know about the hand.

    ``pad_half_width_m`` (x), ``pad_half_length_m`` (z, the pads are centred on the TCP),
    ``finger_thickness_m`` (outward from a pad face along y), ``palm_above_tcp_m`` (from the
    TCP back to the nearest face of the palm and camera), ``max_opening_m``; ``boxes`` and
    ``spheres`` as above."""

    pad_half_width_m: float
    pad_half_length_m: float
    finger_thickness_m: float
    palm_above_tcp_m: float
    max_opening_m: float
    boxes: HandBoxes
    spheres: HandSpheres


def _pose(pos, quat) -> np.ndarray:
    T = np.eye(4)
    m = np.empty(9)
    mujoco.mju_quat2Mat(m, np.asarray(quat, float))
    T[:3, :3] = m.reshape(3, 3)
    T[:3, 3] = pos
    return T


def _geom_boxes(model: mujoco.MjModel, opening_m: float):
    """(names, centres, R, half, finger, pad) of the hand's collision geoms in the TCP frame."""
    data = mujoco.MjData(model)
    for name in rm.FINGER_JOINT_NAMES:
        j = model.joint(name)
        lo, hi = model.jnt_range[j.id]
        data.qpos[j.qposadr[0]] = float(np.clip(0.5 * opening_m, lo, hi))
    mujoco.mj_kinematics(model, data)
    hand = model.body(rm.HAND_BODY).id
    site = model.site(rm.TCP_SITE).id
    R_t, p_t = data.site_xmat[site].reshape(3, 3), data.site_xpos[site]
    fingers = {model.body(n).id for n in rm.FINGER_BODIES}
    out = []
    for g in range(model.ngeom):
        b = int(model.geom_bodyid[g])
        if b != hand and b not in fingers:
            continue
        if model.geom_contype[g] == 0 and model.geom_conaffinity[g] == 0:
            continue
        Rg = data.geom_xmat[g].reshape(3, 3)
        size = np.array(model.geom_size[g], float)
        if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_CYLINDER:
            half = np.array([size[0], size[0], size[1]])
        elif model.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX:
            half = size.copy()
        else:
            half = np.full(3, float(model.geom_rbound[g]))
        name = model.geom(g).name
        out.append((name, R_t.T @ (data.geom_xpos[g] - p_t), R_t.T @ Rg, half, b in fingers,
                    name in rm.FINGER_PAD_GEOMS))
    return out


@lru_cache(maxsize=4)
def hand_model(sphere_cell_m: float = 0.04) -> HandModel:
    """The :class:`HandModel` of our robot (planner spheres on the ``sphere_cell_m`` grid)."""
    model = rm.load_robot_model()
    full = rm.GRIPPER_MAX_WIDTH_M
    g0, g1 = _geom_boxes(model, 0.0), _geom_boxes(model, full)
    c0 = np.array([g[1] for g in g0])
    boxes = HandBoxes(c0, (np.array([g[1] for g in g1]) - c0) / full, np.array([g[2] for g in g0]),
                      np.array([g[3] for g in g0]), tuple(g[0] for g in g0),
                      np.array([g[4] for g in g0]), np.array([g[5] for g in g0]))
    s0, r = hand_spheres_in_tcp(model, sphere_cell_m, 0.0)
    s1, _ = hand_spheres_in_tcp(model, sphere_cell_m, full)
    spheres = HandSpheres(s0, (s1 - s0) / full, r)
    pad = boxes.pad
    pad_half = boxes.half[pad][0]
    pad_R = np.abs(boxes.R[pad][0])
    ext = pad_R @ pad_half  # pad half extents along the TCP axes
    palm = ~boxes.finger
    palm_corners = boxes.corners(0.0, palm)
    finger_corners = boxes.corners(0.0, boxes.finger & ~pad)
    pad_face = float(np.min(np.abs(boxes.centres(0.0)[pad][:, 1])) - ext[1])
    thickness = float(np.max(np.abs(finger_corners[:, 1]))) - max(pad_face, 0.0)
    return HandModel(pad_half_width_m=float(ext[0]), pad_half_length_m=float(ext[2]),
                     finger_thickness_m=thickness,
                     palm_above_tcp_m=float(-np.max(palm_corners[:, 2])), max_opening_m=full,
                     boxes=boxes, spheres=spheres)
