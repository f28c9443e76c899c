"""MuJoCo bodies and geoms for the scene's objects (one builder per object kind).

* primitives (``cube``, ``cuboid``, ``cylinder``): one box / cylinder geom named
  ``obj_<name>``;
* ``mesh`` (an :class:`~grasp_pipeline.objects.model.ObjectModel`): one mesh geom per convex
  collision part (``obj_<name>_p<k>``; MuJoCo collides the convex hull of a mesh, which is
  the part itself) carrying the mass (density × volume), plus the visual mesh
  (``obj_<name>_visual``: seen by the cameras, no collisions, no mass) — so the depth camera
  sees the real shape while contacts use the convex parts. Where the visual mesh is missing,
  the parts are seen.

The body frame is the centre of the object's bounding box (like the primitives), so ground
truth positions mean the same for every kind. Materials: the friction, softness and contact
dimension of ``sim.yaml`` / this module for every geom that collides.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from .config import SimConfig
from .scene_spec import ObjectSpec

#: Prefix of object body and geom names in the model.
OBJECT_PREFIX = "obj_"


def geom_object(geom_name: str) -> str:
    """The object a geom belongs to: a mesh object's collision parts ``obj_<name>_p<k>`` all
    belong to ``obj_<name>``; any other geom name is returned as it is."""
    head, sep, k = geom_name.rpartition("_p")
    return head if sep and k.isdigit() else geom_name
#: Geom group the cameras do not render (they see groups 0-2): objects made invisible.
HIDDEN_GEOM_GROUP = 3
#: Group of a mesh object's visual geom (seen by cameras; it does not collide).
VISUAL_GEOM_GROUP = 2
#: Group of a mesh object's collision parts when a visual mesh is drawn instead.
COLLISION_ONLY_GROUP = 3
#: Objects: torsional/rolling friction coefficients and contact dimension (4: torsional
#: friction too; tests/python/sim/test_sim_grasp_hold.py: a grasp holds by friction).
OBJECT_FRICTION_TORSION = 0.005
OBJECT_FRICTION_ROLL = 0.0001
OBJECT_CONDIM = 4
#: Objects' contact softness: a 4 ms time constant (2 physics steps) and high impedance, like
#: the fingertip pads, so a 40 N squeeze compresses the contact by about a millimetre, not 5.
OBJECT_SOLREF = (0.004, 1.0)
OBJECT_SOLIMP = (0.95, 0.99, 0.001, 0.5, 2.0)


def object_body_name(obj: ObjectSpec | str) -> str:
    """Body name of an object in the model (its geoms start with it too)."""
    return OBJECT_PREFIX + (obj if isinstance(obj, str) else obj.name)


def _material(config: SimConfig) -> dict:
    return dict(density=config.object_density_kg_m3, condim=OBJECT_CONDIM,
                solref=list(OBJECT_SOLREF), solimp=list(OBJECT_SOLIMP),
                friction=[config.object_friction, OBJECT_FRICTION_TORSION, OBJECT_FRICTION_ROLL])


def _body_quat(obj: ObjectSpec) -> list[float]:
    if obj.quat_wxyz is not None:
        return [float(v) for v in obj.quat_wxyz]
    return [math.cos(obj.yaw_rad / 2), 0.0, 0.0, math.sin(obj.yaw_rad / 2)]


def _add_primitive(body, obj: ObjectSpec, config: SimConfig) -> None:
    sx, sy, sz = obj.size_m
    if obj.kind == "cylinder":
        gtype, size = mujoco.mjtGeom.mjGEOM_CYLINDER, [sx / 2, sz / 2, 0.0]
    else:
        gtype, size = mujoco.mjtGeom.mjGEOM_BOX, [sx / 2, sy / 2, sz / 2]
    body.add_geom(name=object_body_name(obj), type=gtype, size=size, rgba=list(obj.rgba),
                  group=0 if obj.camera_visible else HIDDEN_GEOM_GROUP, **_material(config))


def _add_mesh_asset(spec: mujoco.MjSpec, name: str, mesh, offset: np.ndarray, shell: bool) -> None:
    asset = spec.add_mesh()
    asset.name = name
    asset.uservert = (np.asarray(mesh.vertices, float) + offset).reshape(-1).tolist()
    asset.userface = np.asarray(mesh.faces, int).reshape(-1).tolist()
    if shell:  # a visual mesh need not be watertight: no volume-based inertia for it
        asset.inertia = mujoco.mjtMeshInertia.mjMESH_INERTIA_SHELL


def _add_mesh_object(spec: mujoco.MjSpec, body, obj: ObjectSpec, config: SimConfig) -> None:
    model = obj.mesh
    base = object_body_name(obj)
    # model frame: bottom-face centre; body frame: bounding-box centre
    lo, hi = model.bounds_m()
    offset = -0.5 * (lo + hi)
    visual = model.visual if obj.camera_visible else None
    part_group = (COLLISION_ONLY_GROUP if visual is not None else
                  0 if obj.camera_visible else HIDDEN_GEOM_GROUP)
    material = _material(config)
    # overlapping hull parts would count shared volume twice: the mass is the object's volume
    parts_volume = sum(abs(float(p.volume)) for p in model.parts)
    if parts_volume > 0:
        material["density"] = config.object_density_kg_m3 * model.volume_m3() / parts_volume
    for k, part in enumerate(model.parts):
        _add_mesh_asset(spec, f"{base}_p{k}", part, offset, shell=False)
        body.add_geom(name=f"{base}_p{k}", type=mujoco.mjtGeom.mjGEOM_MESH, meshname=f"{base}_p{k}",
                      rgba=list(obj.rgba), group=part_group, **material)
    if visual is not None:
        _add_mesh_asset(spec, f"{base}_visual", visual, offset, shell=True)
        body.add_geom(name=f"{base}_visual", type=mujoco.mjtGeom.mjGEOM_MESH, meshname=f"{base}_visual",
                      rgba=list(obj.rgba), group=VISUAL_GEOM_GROUP, contype=0, conaffinity=0,
                      density=0.0, mass=0.0)


def add_object(spec: mujoco.MjSpec, obj: ObjectSpec, config: SimConfig) -> None:
    """Add ``obj``'s body (free unless ``fixed``) and geoms to ``spec``'s world body."""
    body = spec.worldbody.add_body(name=object_body_name(obj), pos=list(obj.position_m),
                                   quat=_body_quat(obj))
    if not obj.fixed:
        body.add_freejoint(name=object_body_name(obj) + "_free")
    if obj.kind == "mesh":
        _add_mesh_object(spec, body, obj, config)
    else:
        _add_primitive(body, obj, config)
