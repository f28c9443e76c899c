"""Export of the collision model to the C++ state checker (``grasp_pipeline._core``).

:func:`robot_model` turns the robot's MuJoCo chain and sphere model into a
``_core.RobotCollisionModel`` once: per body its parent, fixed rotation/offset and its arm
hinge (axis, anchor, zero angle); joints at fixed values (the finger slides, at the
current finger opening) are folded into the fixed offsets. :func:`collision_scene` turns one
perceived scene (occupancy distance field, object boxes, target-cleared view, object
points, floor and margins) into an immutable ``_core.CollisionScene``. The checker then reproduces
:meth:`StateValidator._python_check_batch` exactly (see ``tests/python/motion``).
"""

from __future__ import annotations

import mujoco
import numpy as np

from .. import _core
from .config import MotionConfig
from .exceptions import MotionError
from .kinematics import ChainKinematics, _axis_angle_batch
from .object_points import ObjectPoints
from .occupancy import OccupancyMap, OrientedBox
from .robot_spheres import RobotSpheres


class CollisionExportError(MotionError):
    """The robot model has a joint the C++ chain cannot represent."""


def _body_rows(robot: RobotSpheres) -> dict[str, np.ndarray]:
    """Chain arrays (B = nbody): parent, fixed R/p (fixed joints folded in), arm hinge."""
    return chain_rows(robot.kin, robot.fixed_qpos)


def chain_rows(kin: ChainKinematics, q_fixed: np.ndarray) -> dict[str, np.ndarray]:
    """Chain arrays of ``kin`` with the non-arm joints at ``q_fixed`` (full qpos) folded in:
    the ``chain`` argument of ``_core.RobotCollisionModel`` and ``_core.ArmIK``."""
    col = {int(a): i for i, a in enumerate(kin.arm_qpos_idx)}
    nb = kin.nbody
    R, p = kin.body_R.copy(), kin.body_pos.copy()
    joint, q0 = np.full(nb, -1), np.zeros(nb)
    axis, anchor = np.tile([0.0, 0.0, 1.0], (nb, 1)), np.zeros((nb, 3))
    for b in range(nb):
        for jt, adr, ax, anc, zero in kin.joints[b]:
            if adr in col:
                if joint[b] >= 0 or len(kin.joints[b]) != 1:
                    raise CollisionExportError(f"body {b}: an arm joint must be the body's only joint")
                joint[b], axis[b], anchor[b], q0[b] = col[adr], ax, anc, zero
                continue
            val = float(q_fixed[adr]) - zero
            if jt == mujoco.mjtJoint.mjJNT_SLIDE:
                p[b] = p[b] + R[b] @ ax * val
            else:  # a hinge at a fixed angle
                Rn = R[b] @ _axis_angle_batch(ax, np.array([val]))[0]
                p[b] = p[b] + R[b] @ anc - Rn @ anc
                R[b] = Rn
    parent = kin.parent.copy()
    parent[0] = 0
    return {"body_parent": parent, "body_rotation": R, "body_position": p, "body_joint": joint,
            "joint_axis": axis, "joint_anchor": anchor, "joint_q0_rad": q0}


def robot_model(robot: RobotSpheres, q_min_rad: np.ndarray, q_max_rad: np.ndarray):
    """The ``_core.RobotCollisionModel`` of ``robot`` at its current finger opening."""
    sph = robot.spheres
    arrays = _body_rows(robot)
    arrays.update({
        "sphere_body": sph.body, "sphere_center_m": sph.center_local, "sphere_radius_m": sph.radius,
        "sphere_geom": sph.geom, "env_sphere": robot.env_mask.astype(int),
        "hand_sphere": robot.hand_mask.astype(int), "pair_i": robot.pair_i, "pair_j": robot.pair_j,
        "q_min_rad": np.asarray(q_min_rad, dtype=float), "q_max_rad": np.asarray(q_max_rad, dtype=float),
        "self_margin_m": float(robot.self_margin_m)})
    return _core.RobotCollisionModel(arrays)


def _cleared_arrays(env_cleared: OccupancyMap | None) -> dict | None:
    region = env_cleared.cleared_region() if env_cleared is not None else None
    if region is None:
        return None
    box, pts, fine_m = region
    return {"center_m": box.center, "rotation": box.R, "extents_m": box.extents, "points_m": pts,
            "pad_m": env_cleared.pad_m, "fine_m": fine_m}


def collision_scene(config: MotionConfig, env: OccupancyMap | None, boxes: list[OrientedBox],
                    env_cleared: OccupancyMap | None = None, points: ObjectPoints | None = None):
    """The ``_core.CollisionScene`` of one perceived scene (``env_cleared``: the map's
    target-cleared view, used for the hand spheres when target contact is allowed;
    ``points``: the objects modelled by their points)."""
    kw: dict = {"collision_margin_m": config.collision_margin_m, "floor_z_m": config.floor_z_m,
                "has_env": env is not None, "cleared": _cleared_arrays(env_cleared),
                "points": None if points is None or not len(points.points) else points.core_arrays()}
    if env is not None:
        kw.update(voxel_size_m=env.voxel_size_m, inflation_m=env.inflation_m, origin_m=env.origin_m,
                  field_m=env.distance_field_m)
    if boxes:
        kw.update(box_centers_m=np.array([b.center for b in boxes]),
                  box_rotations=np.array([b.R for b in boxes]),
                  box_extents_m=np.array([b.extents for b in boxes]))
    return _core.CollisionScene(**kw)
