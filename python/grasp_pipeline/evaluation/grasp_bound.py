"""The geometric bound of a grasp: could the hand grasp an object at all — from straight above,
with a tilted approach, from some side? Evaluation only: it reads the true shape and pose.

For an approach direction a, an object is graspable when the narrowest width of its projection
onto the plane perpendicular to a (the smallest extent along a closing direction c ⟂ a) is at
most ``max_width_m``. The search runs over closing directions instead of approaches: the
approaches perpendicular to c come within asin(|c_z|) of straight down, so c serves an
approach tilted at most θ from the table's normal exactly when c rises at most θ above the
table plane. With c on the upper half sphere:

* ``top_down``: some horizontal c (the narrowest width of the object's footprint);
* ``tilted``: some c at most ``tilted_limit_deg`` above the table plane;
* ``any_side``: any c (approaches down to horizontal: side grasps too);
* ``none``: no c.

The classes are nested (top_down ⊂ tilted ⊂ any_side); an object's label is its tightest one.

**Table rule** (``min_contact_height_m`` > 0): both pads must touch the object above the table —
the object's points within ``contact_band_m`` of its outermost point along +c and along −c
must reach ``min_contact_height_m`` above the table. A pad cannot press on a face lying on the
table: a plate lying flat is narrow only between a pad on top and one under it, so it is
``none``. ``label_width_only`` is the label by widths alone (the rule off).

**Directions**, on the convex hull of the object's collision parts (same projections as the
object): the horizontal circle every 0.25° and, per hull edge, the horizontal direction
perpendicular to it (a convex polygon is narrowest across one of its edges: top_down by widths
is exact); the circle ``tilted_limit_deg`` above the table every 0.5° and, per hull edge, its
two points perpendicular to the edge (the tilted class's boundary, exact the same way); the
hull's face normals (a face flat on one pad: exact); 4000 directions spread evenly over the
half sphere (Fibonacci, about 2.3° apart); then an 11 × 11 grid of 0.3° steps (± 1.5°) around
the 4 narrowest directions of each class. A width changes by at most 2ρ per radian of turn of
c (ρ: the largest distance of a hull point from the object's centre), so where the narrowest
direction lies in a refined grid the width is overestimated by at most 2ρ · 0.0037 — 0.4 mm
for an object 10 cm across — and by at most 2ρ · 0.024 (2.4 mm at 10 cm) elsewhere: far
below the hand's 5 mm margin, and never in the object's favour.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Iterable, Optional

import numpy as np
import trimesh

from ..sim.ground_truth import object_truths
from .config import GraspBoundConfig

#: The labels, tightest first.
LABELS = ("top_down", "tilted", "any_side", "none")
#: The classes of approach (each label but ``none``).
CLASSES = LABELS[:3]

HORIZONTAL_STEP_DEG = 0.25
TILT_CIRCLE_STEP_DEG = 0.5
SPREAD_DIRECTIONS = 4000
REFINE_SEEDS = 4
REFINE_HALF_STEPS = 5
REFINE_STEP_DEG = 0.3
CYLINDER_SECTIONS = 64


@dataclass(frozen=True)
class ConvexShape:
    """A convex hull: its vertices (n, 3), unit edge directions (k, 3), unit face normals (f, 3)."""

    vertices: np.ndarray
    edges: np.ndarray
    normals: np.ndarray

    @classmethod
    def of_points(cls, points) -> "ConvexShape":
        """The hull of ``points`` (m); a flat or degenerate set keeps its points alone."""
        pts = np.asarray(points, dtype=float).reshape(-1, 3)
        try:
            hull = trimesh.convex.convex_hull(pts)
        except Exception:  # qhull refuses flat sets: the points still bound the widths
            return cls(np.unique(pts, axis=0), np.zeros((0, 3)), np.zeros((0, 3)))
        v = np.asarray(hull.vertices, dtype=float)
        e = v[hull.edges_unique[:, 1]] - v[hull.edges_unique[:, 0]]
        e = e[np.linalg.norm(e, axis=1) > 1e-12]
        n = np.unique(np.round(np.asarray(hull.face_normals, dtype=float), 9), axis=0)
        return cls(v, e / np.linalg.norm(e, axis=1, keepdims=True), n)

    def posed(self, T: np.ndarray) -> "ConvexShape":
        """The same hull moved by the 4x4 pose ``T``."""
        R, p = np.asarray(T, float)[:3, :3], np.asarray(T, float)[:3, 3]
        return ConvexShape(self.vertices @ R.T + p, self.edges @ R.T, self.normals @ R.T)


def object_shape(obj) -> ConvexShape:
    """The convex hull of a scene object (:class:`~grasp_pipeline.sim.scene_spec.ObjectSpec`)
    in its body frame (the centre of its bounding box), as the simulator collides it: a mesh
    object's collision parts (scaled), a box, or a cylinder."""
    sx, sy, sz = (0.5 * float(s) for s in obj.size_m)
    if obj.kind == "mesh":
        lo, hi = obj.mesh.bounds_m()
        pts = np.vstack([np.asarray(p.vertices, float) for p in obj.mesh.parts]) - 0.5 * (lo + hi)
    elif obj.kind == "cylinder":
        t = np.linspace(0.0, 2 * math.pi, CYLINDER_SECTIONS, endpoint=False)
        ring = np.stack([sx * np.cos(t), sx * np.sin(t)], axis=1)
        pts = np.vstack([np.column_stack([ring, np.full(len(t), z)]) for z in (-sz, sz)])
    else:
        pts = np.array([[x, y, z] for x in (-sx, sx) for y in (-sy, sy) for z in (-sz, sz)])
    return ConvexShape.of_points(pts)


@dataclass(frozen=True)
class GraspBound:
    """One object's bound: ``label`` (with the table rule) and ``label_width_only`` (by widths
    alone), and per class the narrowest width found [m] (None: no usable closing direction)."""

    label: str
    label_width_only: str
    narrowest_m: dict
    narrowest_width_only_m: dict

    def to_dict(self) -> dict:
        mm = lambda d: {k: None if v is None else round(1e3 * v, 1) for k, v in d.items()}  # noqa: E731
        return {"label": self.label, "label_width_only": self.label_width_only,
                "narrowest_mm": mm(self.narrowest_m),
                "narrowest_width_only_mm": mm(self.narrowest_width_only_m)}


# ------------------------------------------------------------------------------ directions


def _circle(elevation_rad: float, step_deg: float) -> np.ndarray:
    """Directions ``elevation_rad`` above the table plane, every ``step_deg`` of azimuth (half a
    turn on the horizontal circle, where c and −c are the same closing)."""
    turn = 180.0 if elevation_rad == 0.0 else 360.0
    az = np.radians(np.arange(0.0, turn, step_deg))
    ce = math.cos(elevation_rad)
    return np.column_stack([ce * np.cos(az), ce * np.sin(az), np.full(len(az), math.sin(elevation_rad))])


def _perpendicular_on_circle(edges: np.ndarray, elevation_rad: float) -> np.ndarray:
    """Per edge e, the directions ``elevation_rad`` above the table plane perpendicular to e."""
    ce, se = math.cos(elevation_rad), math.sin(elevation_rad)
    a, b, c = edges[:, 0] * ce, edges[:, 1] * ce, -edges[:, 2] * se
    r = np.hypot(a, b)
    ok = (r > 1e-12) & (np.abs(c) <= r)
    phi, d = np.arctan2(b[ok], a[ok]), np.arccos(np.clip(c[ok] / r[ok], -1.0, 1.0))
    az = np.concatenate([phi + d, phi - d])
    z = 0.0 if elevation_rad == 0.0 else se  # exactly horizontal on the horizontal circle
    return np.column_stack([ce * np.cos(az), ce * np.sin(az), np.full(len(az), z)])


def _spread(n: int) -> np.ndarray:
    """``n`` directions spread evenly over the upper half sphere (a Fibonacci lattice)."""
    k = np.arange(n) + 0.5
    z = k / n
    r = np.sqrt(1.0 - z * z)
    az = math.pi * (3.0 - math.sqrt(5.0)) * k
    return np.column_stack([r * np.cos(az), r * np.sin(az), z])


def _upper(c: np.ndarray) -> np.ndarray:
    """Unit directions with c_z ≥ 0 (c and −c are the same closing)."""
    c = c / np.linalg.norm(c, axis=1, keepdims=True)
    return np.where(c[:, 2:3] < 0.0, -c, c)


def _around(seeds: np.ndarray) -> np.ndarray:
    """A grid of ``REFINE_STEP_DEG`` steps around each seed direction (on its tangent plane)."""
    s = np.tan(np.radians(REFINE_STEP_DEG)) * np.arange(-REFINE_HALF_STEPS, REFINE_HALF_STEPS + 1)
    gu, gv = (g.ravel() for g in np.meshgrid(s, s))
    out = []
    for c in seeds:
        u = np.cross(c, [0.0, 0.0, 1.0] if abs(c[2]) < 0.9 else [1.0, 0.0, 0.0])
        u /= np.linalg.norm(u)
        v = np.cross(c, u)
        out.append(c + gu[:, None] * u + gv[:, None] * v)
    return _upper(np.vstack(out)) if out else np.zeros((0, 3))


def first_directions(shape: ConvexShape, tilted_limit_rad: float) -> np.ndarray:
    """The candidate closing directions before refinement (see the module doc)."""
    parts = [_circle(0.0, HORIZONTAL_STEP_DEG), _perpendicular_on_circle(shape.edges, 0.0),
             _circle(tilted_limit_rad, TILT_CIRCLE_STEP_DEG),
             _perpendicular_on_circle(shape.edges, tilted_limit_rad),
             _spread(SPREAD_DIRECTIONS), np.array([[0.0, 0.0, 1.0]])]
    if len(shape.normals):
        parts.append(_upper(shape.normals))
    return np.vstack(parts)


# ------------------------------------------------------------------------------ widths


def widths(vertices: np.ndarray, directions: np.ndarray, config: GraspBoundConfig) -> tuple:
    """(width along each direction [m], whether the table rule allows it) for hull
    ``vertices`` given with z measured from the table top."""
    d = vertices @ directions.T
    hi, lo = d.max(axis=0), d.min(axis=0)
    if config.min_contact_height_m <= 0.0:
        return hi - lo, np.ones(len(hi), dtype=bool)
    z = vertices[:, 2:3]
    z_lo = np.where(d <= lo + config.contact_band_m, z, -np.inf).max(axis=0)
    z_hi = np.where(d >= hi - config.contact_band_m, z, -np.inf).max(axis=0)
    return hi - lo, np.minimum(z_lo, z_hi) >= config.min_contact_height_m


def _class_masks(directions: np.ndarray, tilted_limit_rad: float) -> dict:
    cz = directions[:, 2]
    return {"top_down": np.abs(cz) <= 1e-9, "tilted": cz <= math.sin(tilted_limit_rad) + 1e-9,
            "any_side": np.ones(len(cz), dtype=bool)}


def _narrowest(w: np.ndarray, usable: np.ndarray, masks: dict) -> dict:
    out = {}
    for name, m in masks.items():
        m = m & usable
        out[name] = float(w[m].min()) if m.any() else None
    return out


def _label(narrowest: dict, max_width_m: float) -> str:
    for name in CLASSES:
        if narrowest[name] is not None and narrowest[name] <= max_width_m:
            return name
    return "none"


def _seeds(w: np.ndarray, usable: np.ndarray, masks: dict, directions: np.ndarray) -> np.ndarray:
    """The ``REFINE_SEEDS`` narrowest directions of the tilted and any_side classes, with the
    table rule and without."""
    picks = []
    for name in ("tilted", "any_side"):
        for ok in (usable, np.ones_like(usable)):
            idx = np.flatnonzero(masks[name] & ok)
            picks.extend(idx[np.argsort(w[idx])[:REFINE_SEEDS]])
    return directions[np.unique(np.asarray(picks, dtype=int))]


def grasp_bound(shape: ConvexShape, table_z_m: float, config: GraspBoundConfig) -> GraspBound:
    """The bound of one object whose hull ``shape`` is given in the world frame (z up, the
    table top at ``table_z_m``)."""
    v = shape.vertices - np.array([0.0, 0.0, table_z_m])
    tilt = math.radians(config.tilted_limit_deg)
    dirs = first_directions(shape, tilt)
    w, usable = widths(v, dirs, config)
    fine = _around(_seeds(w, usable, _class_masks(dirs, tilt), dirs))
    if len(fine):
        w2, usable2 = widths(v, fine, config)
        dirs, w, usable = np.vstack([dirs, fine]), np.concatenate([w, w2]), np.concatenate([usable, usable2])
    masks = _class_masks(dirs, tilt)
    with_rule = _narrowest(w, usable, masks)
    alone = _narrowest(w, np.ones_like(usable), masks)
    return GraspBound(_label(with_rule, config.max_width_m), _label(alone, config.max_width_m),
                      with_rule, alone)


def object_bounds(posed: Iterable[tuple], table_z_m: float, config: GraspBoundConfig,
                  shapes: Optional[dict] = None) -> dict:
    """{name: :class:`GraspBound`} of ``(ObjectSpec, 4x4 world pose)`` pairs; ``shapes``: their
    hulls in the body frame by name, when already computed."""
    out = {}
    for obj, T in posed:
        shape = shapes[obj.name] if shapes is not None and obj.name in shapes else object_shape(obj)
        out[obj.name] = grasp_bound(shape.posed(T), table_z_m, config)
    return out


def bounds_of_spec(spec, config: GraspBoundConfig) -> dict:
    """The bounds of a scene's objects where the scene places them (a pile: where they settled)."""
    return object_bounds(((o, o.pose()) for o in spec.objects), spec.table_top_z_m, config)


def bounds_of_world(world, config: GraspBoundConfig, shapes: Optional[dict] = None) -> dict:
    """The bounds of a running world's objects where they are now."""
    specs = {o.name: o for o in world.scene.objects}
    posed = ((specs[t.name], t.T_world_object) for t in object_truths(world))
    return object_bounds(posed, world.scene.table_top_z_m, config, shapes)
