"""Cluttered scenes in the protocols of the VGN/GIGA grasping benchmarks: ``packed`` and ``pile``.

Both draw ``objects_per_scene`` objects (uniformly, with replacement, from a list of
:class:`~grasp_pipeline.objects.model.ObjectModel`) with a seeded generator, so the same seed
and object set always give the same scene.

* **packed**: each object upright, random yaw, scale U(``packed_scale``), centre uniform in
  the ``square_size_m`` square on the table; rejected when it touches an object already placed
  (MuJoCo's contacts of the real collision parts, within ``placement_gap_m``); up to
  ``placement_attempts`` tries per object, then it is left out.
* **pile**: each object with a uniformly random 3-D orientation, scale U(``pile_scale``), its
  lowest point ``drop_height_m`` above the table over a random point of the square, dropped
  one by one into a box standing on the square and simulated for ``settle_s``; the box is
  then removed, the pile settles again, and objects whose centre left the square (or the
  table) are removed.

The returned :class:`~.scene_spec.SceneSpec` holds the final poses; ``SimWorld`` builds it
like any scene (the objects start where they came to rest).
"""

from __future__ import annotations

import math
from typing import Sequence

import mujoco
import numpy as np

from ..robot.description import READY_Q
from .clutter_config import ClutterConfig
from .config import SimConfig
from .exceptions import SceneError
from .object_geoms import add_object, object_body_name
from .scene_spec import ObjectSpec, SceneSpec
from .scenes import REST_CLEARANCE_M  # objects start this far above the table (no initial contact)
from .work_cell import table_top_z_m

TABLE_THICKNESS_M = 0.02
SETTLE_SPEED_MPS = 0.01     # a pile has settled when every object is slower than this


def _choose(models: Sequence, rng: np.random.Generator, n: int) -> list:
    if not models:
        raise SceneError("no objects to build a cluttered scene from")
    return [models[int(rng.integers(len(models)))] for _ in range(n)]


def _spec_for(model, index: int, pos, quat=None, yaw: float = 0.0) -> ObjectSpec:
    return ObjectSpec(f"{model.name}_{index}", "mesh", tuple(float(e) for e in model.extents_m()),
                      tuple(float(p) for p in pos), yaw_rad=float(yaw), rgba=tuple(model.rgba),
                      mesh=model, quat_wxyz=None if quat is None else tuple(float(q) for q in quat),
                      category=model.category or model.name)


def _base_spec(sim: SimConfig, walls: Sequence[tuple] = ()) -> mujoco.MjSpec:
    """A world with just the table top (and optional fixed wall boxes)."""
    spec = mujoco.MjSpec()
    spec.option.timestep = sim.timestep_s
    spec.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
    spec.option.impratio = 10
    spec.worldbody.add_geom(name="table", type=mujoco.mjtGeom.mjGEOM_BOX,
                            size=[1.0, 1.0, TABLE_THICKNESS_M / 2],
                            pos=[0.5, 0.0, table_top_z_m() - TABLE_THICKNESS_M / 2])
    for k, (centre, half) in enumerate(walls):
        spec.worldbody.add_geom(name=f"box_wall{k}", type=mujoco.mjtGeom.mjGEOM_BOX,
                                size=list(half), pos=list(centre))
    return spec


def _touches(objects: list[ObjectSpec], sim: SimConfig, gap_m: float) -> bool:
    """True when the last object is within ``gap_m`` of any other (real collision parts)."""
    spec = _base_spec(sim)
    for o in objects:
        add_object(spec, o, sim)
    for g in spec.geoms:
        g.margin = gap_m
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    last = model.body(object_body_name(objects[-1])).id
    for i in range(data.ncon):
        c = data.contact[i]
        b1, b2 = model.geom_bodyid[c.geom1], model.geom_bodyid[c.geom2]
        if last in (b1, b2) and 0 not in (b1, b2) and c.dist < gap_m:
            return True
    return False


def _square_xy(rng: np.random.Generator, cfg: ClutterConfig, margin_m: float = 0.0) -> np.ndarray:
    half = 0.5 * cfg.square_size_m - margin_m
    return np.asarray(cfg.square_center_m, float) + rng.uniform(-half, half, size=2)


def packed_scene(models: Sequence, seed: int, cfg: ClutterConfig, sim: SimConfig) -> SceneSpec:
    """VGN's packed protocol (see the module doc)."""
    rng = np.random.default_rng(seed)
    placed: list[ObjectSpec] = []
    notes = []
    for i, model in enumerate(_choose(models, rng, cfg.objects_per_scene)):
        scaled = model.scaled(float(rng.uniform(*cfg.packed_scale)))
        z = table_top_z_m() + 0.5 * float(scaled.extents_m()[2]) + REST_CLEARANCE_M
        for _ in range(cfg.placement_attempts):
            cand = _spec_for(scaled, i, (*_square_xy(rng, cfg), z), yaw=rng.uniform(0, 2 * math.pi))
            if not _touches(placed + [cand], sim, cfg.placement_gap_m):
                placed.append(cand)
                break
        else:
            notes.append(f"{model.name}_{i}: no free place in {cfg.placement_attempts} attempts")
    if not placed:
        raise SceneError(f"packed scene {seed}: no object could be placed")
    return SceneSpec(f"packed_{seed}", tuple(placed), table_top_z_m(),
                     tuple(float(v) for v in READY_Q), seed=seed, notes=tuple(notes))


def _random_quat(rng: np.random.Generator) -> np.ndarray:
    """A uniformly random unit quaternion (w, x, y, z) (Shoemake)."""
    u1, u2, u3 = rng.uniform(size=3)
    a, b = math.sqrt(1 - u1), math.sqrt(u1)
    x, y = a * math.sin(2 * math.pi * u2), a * math.cos(2 * math.pi * u2)
    z, w = b * math.sin(2 * math.pi * u3), b * math.cos(2 * math.pi * u3)
    return np.array([w, x, y, z])


def _box_walls(cfg: ClutterConfig) -> list[tuple]:
    cx, cy = cfg.square_center_m
    h, t, s = cfg.box_wall_height_m, cfg.box_wall_thickness_m, cfg.square_size_m
    z = table_top_z_m() + h / 2
    off = s / 2 + t / 2
    return [((cx + off, cy, z), (t / 2, s / 2 + t, h / 2)), ((cx - off, cy, z), (t / 2, s / 2 + t, h / 2)),
            ((cx, cy + off, z), (s / 2, t / 2, h / 2)), ((cx, cy - off, z), (s / 2, t / 2, h / 2))]


def _simulate(objects: list[ObjectSpec], sim: SimConfig, walls, duration_s: float) -> list[ObjectSpec]:
    """Let ``objects`` fall/settle for up to ``duration_s``; their poses afterwards."""
    spec = _base_spec(sim, walls)
    for o in objects:
        add_object(spec, o, sim)
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    steps = int(round(duration_s / model.opt.timestep))
    for k in range(steps):
        mujoco.mj_step(model, data)
        if k > steps // 3 and k % 50 == 0 and np.max(np.abs(data.qvel)) < SETTLE_SPEED_MPS:
            break
    out = []
    for o in objects:
        b = model.body(object_body_name(o)).id
        out.append(ObjectSpec(o.name, o.kind, o.size_m, tuple(float(v) for v in data.xpos[b]),
                              rgba=o.rgba, mesh=o.mesh, quat_wxyz=tuple(float(v) for v in data.xquat[b]),
                              category=o.category))
    return out


def _drop_pose(scaled, rng: np.random.Generator, cfg: ClutterConfig):
    quat = _random_quat(rng)
    R = np.zeros(9)
    mujoco.mju_quat2Mat(R, quat)
    lo, hi = scaled.bounds_m()
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
    corners -= 0.5 * (lo + hi)                    # body frame = bounding-box centre
    lowest = float(np.min(corners @ R.reshape(3, 3).T[:, 2]))
    radius = 0.5 * float(np.linalg.norm(hi - lo))
    xy = _square_xy(rng, cfg, margin_m=min(radius, 0.4 * cfg.square_size_m))
    return (*xy, table_top_z_m() + cfg.drop_height_m - lowest), quat


def _inside(o: ObjectSpec, cfg: ClutterConfig) -> bool:
    c = np.asarray(cfg.square_center_m, float)
    p = np.asarray(o.position_m, float)
    return bool(np.all(np.abs(p[:2] - c) <= 0.5 * cfg.square_size_m) and p[2] > table_top_z_m())


def pile_scene(models: Sequence, seed: int, cfg: ClutterConfig, sim: SimConfig) -> SceneSpec:
    """VGN's pile protocol (see the module doc)."""
    rng = np.random.default_rng(seed)
    walls = _box_walls(cfg)
    objects: list[ObjectSpec] = []
    for i, model in enumerate(_choose(models, rng, cfg.objects_per_scene)):
        scaled = model.scaled(float(rng.uniform(*cfg.pile_scale)))
        pos, quat = _drop_pose(scaled, rng, cfg)
        objects = _simulate(objects + [_spec_for(scaled, i, pos, quat=quat)], sim, walls, cfg.settle_s)
    settled = _simulate(objects, sim, (), cfg.settle_s)   # the box is removed
    kept = [o for o in settled if _inside(o, cfg)]
    kept_names = {o.name for o in kept}
    notes = tuple(f"{o.name}: left the square after the box was removed" for o in settled
                  if o.name not in kept_names)
    if not kept:
        raise SceneError(f"pile scene {seed}: every object left the square")
    return SceneSpec(f"pile_{seed}", tuple(kept), table_top_z_m(), tuple(float(v) for v in READY_Q),
                     seed=seed, notes=notes)
