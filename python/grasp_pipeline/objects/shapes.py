"""Geometry generators for the built-in objects: every function returns a list of CONVEX parts.

Each part is a watertight ``trimesh.Trimesh`` with outward normals (the convex hull of
generated points), so the union of the parts is the object and no convex decomposition is
needed. Lengths are metres. Generators build in a convenient local frame;
:func:`standing_on_table` moves the parts so that the centre of the bottom face of their
axis-aligned bounding box is the origin (the object stands on z = 0).

Hollow shapes (mug, bowl) are rings of wedge segments: each segment is the hull of an outer
arc and the inner chord, so the inside is a regular polygon and the outside a finer one.
Neighbouring parts share faces instead of overlapping where that is easy (walls sit on the
base, L/T/cross arms butt against each other), so the summed part volume is the real one.
"""

from __future__ import annotations

import numpy as np
import trimesh

from .model import MeshError


def convex_part(points_m) -> trimesh.Trimesh:
    """The convex hull of ``points_m`` (N, 3) as a watertight mesh with outward normals."""
    pts = np.unique(np.round(np.asarray(points_m, dtype=float), 12), axis=0)
    if len(pts) < 4:
        raise MeshError(f"convex part: need at least 4 distinct points, got {len(pts)}")
    hull = trimesh.convex.convex_hull(pts)
    if not (hull.is_watertight and hull.volume > 1e-12):
        raise MeshError("convex part: points are degenerate (flat or collinear), no volume")
    return hull


def standing_on_table(parts: list) -> list:
    """``parts`` translated so their bounding box's bottom-face centre is the origin."""
    lo = np.min([p.bounds[0] for p in parts], axis=0)
    hi = np.max([p.bounds[1] for p in parts], axis=0)
    shift = -np.array([(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0, lo[2]])
    moved = [p.copy().apply_translation(shift) for p in parts]
    for p in moved:  # remove the round-off of the translation on the bottom face
        v = p.vertices.copy()
        v[np.abs(v[:, 2]) < 1e-12, 2] = 0.0
        p.vertices = v
    return moved


def _ring_points(radius_m: float, z_m: float, angles_rad) -> np.ndarray:
    a = np.asarray(angles_rad, dtype=float)
    return np.column_stack([radius_m * np.cos(a), radius_m * np.sin(a), np.full(a.shape, z_m)])


def _polygon_prism(radius_m: float, sides: int, z0_m: float, z1_m: float) -> trimesh.Trimesh:
    angles = 2.0 * np.pi * np.arange(sides) / sides
    return convex_part(np.vstack([_ring_points(radius_m, z0_m, angles),
                                  _ring_points(radius_m, z1_m, angles)]))


# ---------------------------------------------------------------- VGN-style blocks


def box_parts(size_x_m: float, size_y_m: float, size_z_m: float) -> list:
    """A cuboid (a cube when the three sizes are equal)."""
    return [trimesh.creation.box(extents=(size_x_m, size_y_m, size_z_m))]


def cylinder_parts(radius_m: float, height_m: float, sections: int = 24) -> list:
    """An upright circular cylinder (a polygonal prism with ``sections`` sides)."""
    return [_polygon_prism(radius_m, sections, 0.0, height_m)]


def triangular_prism_parts(side_m: float, length_m: float, lying: bool = True) -> list:
    """An equilateral triangular prism: ``lying`` on a rectangular face (a roof shape with
    the axis along x) or standing on a triangular face (axis along z)."""
    h = side_m * np.sqrt(3.0) / 2.0
    tri = np.array([[-side_m / 2.0, 0.0], [side_m / 2.0, 0.0], [0.0, h]])
    if lying:  # triangle in the y-z plane, extruded along x
        pts = [(x, u, v) for x in (-length_m / 2.0, length_m / 2.0) for u, v in tri]
    else:  # triangle in the x-y plane, extruded along z
        pts = [(u, v, z) for z in (0.0, length_m) for u, v in tri]
    return [convex_part(pts)]


def circular_segment_parts(radius_m: float, sagitta_m: float, thickness_m: float,
                           arc_points: int = 13) -> list:
    """A slab whose outline is a circular segment (the part of a disk of ``radius_m`` beyond
    a chord, ``sagitta_m`` deep), ``thickness_m`` thick, lying flat on the table."""
    if not 0.0 < sagitta_m <= radius_m:
        raise MeshError(f"circular segment: sagitta {sagitta_m} m must be in (0, radius]")
    half = np.arccos((radius_m - sagitta_m) / radius_m)
    angles = np.linspace(-half, half, arc_points)
    return [convex_part(np.vstack([_ring_points(radius_m, 0.0, angles),
                                   _ring_points(radius_m, thickness_m, angles)]))]


# ---------------------------------------------------------------- revolved: bottles, cans


def revolved_parts(profile_rz_m, sections: int = 24) -> list:
    """A solid of revolution about z from a ``profile_rz_m`` list of (radius, z) points from
    bottom to top: one convex frustum per consecutive pair of points (pairs at the same z,
    i.e. steps such as the lip of a cap, only change the radius)."""
    prof = [(float(r), float(z)) for r, z in profile_rz_m]
    angles = 2.0 * np.pi * np.arange(sections) / sections
    parts = []
    for (r0, z0), (r1, z1) in zip(prof[:-1], prof[1:]):
        if z1 - z0 < 1e-6:
            continue
        parts.append(convex_part(np.vstack([_ring_points(r0, z0, angles),
                                            _ring_points(r1, z1, angles)])))
    if not parts:
        raise MeshError("revolved profile: needs at least two points at different heights")
    return parts


def bottle_profile(radius_m: float, height_m: float, neck_radius_m: float,
                   neck_m: float, shoulder_m: float) -> list:
    """(r, z) profile of a bottle: a chamfered base, a body, a conical shoulder, a neck and
    a slightly wider cap of ``neck_m`` / 2 on top."""
    chamfer = min(0.004, radius_m * 0.15)
    cap = neck_m / 2.0
    body_top = height_m - neck_m - shoulder_m
    cap_r = neck_radius_m + 0.0015
    return [(radius_m - chamfer, 0.0), (radius_m, chamfer), (radius_m, body_top),
            (neck_radius_m, body_top + shoulder_m), (neck_radius_m, height_m - cap),
            (cap_r, height_m - cap), (cap_r, height_m)]


def can_profile(radius_m: float, height_m: float) -> list:
    """(r, z) profile of a beverage or food can: tapered bottom and top rims."""
    taper = min(0.008, height_m * 0.1)
    return [(radius_m - 0.003, 0.0), (radius_m, taper), (radius_m, height_m - taper),
            (radius_m - 0.004, height_m)]


def bottle_parts(radius_m: float, height_m: float, neck_radius_m: float, neck_m: float,
                 shoulder_m: float, sections: int = 24) -> list:
    """A bottle: base, body, shoulder, neck and cap frustums (see :func:`bottle_profile`)."""
    return revolved_parts(bottle_profile(radius_m, height_m, neck_radius_m, neck_m, shoulder_m),
                          sections)


def can_parts(radius_m: float, height_m: float, sections: int = 24) -> list:
    """A can: bottom rim, straight body, top rim (see :func:`can_profile`)."""
    return revolved_parts(can_profile(radius_m, height_m), sections)


# ---------------------------------------------------------------- hollow: mugs, bowls


def wall_ring_parts(bottom_m: tuple, top_m: tuple, segments: int) -> list:
    """A (possibly flared) wall of ``segments`` convex wedges. ``bottom_m`` and ``top_m`` are
    (inner radius, outer radius, z); each wedge is the hull of its outer arc (three points
    per level) and inner chord (two points per level)."""
    step = 2.0 * np.pi / segments
    parts = []
    for k in range(segments):
        a0 = k * step
        outer = [a0, a0 + step / 2.0, a0 + step]
        pts = []
        for r_in, r_out, z in (bottom_m, top_m):
            pts.append(_ring_points(r_out, z, outer))
            pts.append(_ring_points(r_in, z, [a0, a0 + step]))
        parts.append(convex_part(np.vstack(pts)))
    return parts


def handle_parts(attach_x_m: float, centre_z_m: float, reach_m: float, thickness_m: float,
                 segments: int = 6, section_points: int = 8) -> list:
    """A D-shaped handle in the x-z plane: a half ring of radius ``reach_m`` centred at
    (``attach_x_m``, 0, ``centre_z_m``) bulging towards +x, of round section ``thickness_m``."""
    phis = np.linspace(-np.pi / 2.0, np.pi / 2.0, segments + 1)
    psis = 2.0 * np.pi * np.arange(section_points) / section_points
    half_t = thickness_m / 2.0

    def section(phi: float) -> np.ndarray:
        radial = np.array([np.cos(phi), 0.0, np.sin(phi)])
        centre = np.array([attach_x_m, 0.0, centre_z_m]) + reach_m * radial
        return np.array([centre + half_t * (np.cos(s) * radial + np.sin(s) * np.array([0, 1.0, 0]))
                         for s in psis])

    return [convex_part(np.vstack([section(p0), section(p1)])) for p0, p1 in zip(phis[:-1], phis[1:])]


def mug_parts(radius_m: float, height_m: float, wall_m: float = 0.005, bottom_m: float = 0.006,
              handle_reach_m: float = 0.022, handle_thickness_m: float = 0.009,
              segments: int = 12) -> list:
    """A mug: a flat bottom disk, a straight wall ring on it and a handle on the +x side."""
    r_in = radius_m - wall_m
    parts = [_polygon_prism(radius_m, 2 * segments, 0.0, bottom_m)]
    parts += wall_ring_parts((r_in, radius_m, bottom_m), (r_in, radius_m, height_m), segments)
    attach_x = r_in + handle_thickness_m / 2.0 + 0.0005  # the handle ends sink into the wall
    centre_z = bottom_m + (height_m - bottom_m) * 0.55
    reach = min(handle_reach_m, (height_m - bottom_m) * 0.4)
    parts += handle_parts(attach_x, centre_z, reach, handle_thickness_m)
    return parts


def bowl_parts(outer_profile_rz_m, wall_m: float = 0.004, base_m: float = 0.005,
               segments: int = 10) -> list:
    """A bowl: a base disk of the first profile radius, then one wall ring per pair of
    (outer radius, z) points of ``outer_profile_rz_m`` (z measured from the base top)."""
    prof = [(float(r), float(z) + base_m) for r, z in outer_profile_rz_m]
    parts = [_polygon_prism(prof[0][0], 2 * segments, 0.0, base_m)]
    for (r0, z0), (r1, z1) in zip(prof[:-1], prof[1:]):
        parts += wall_ring_parts((r0 - wall_m, r0, z0), (r1 - wall_m, r1, z1), segments)
    return parts


# ---------------------------------------------------------------- flat composite blocks


def _slab(x0_m: float, x1_m: float, y0_m: float, y1_m: float, thickness_m: float):
    box = trimesh.creation.box(extents=(x1_m - x0_m, y1_m - y0_m, thickness_m))
    return box.apply_translation(((x0_m + x1_m) / 2.0, (y0_m + y1_m) / 2.0, thickness_m / 2.0))


def l_block_parts(long_m: float, short_m: float, width_m: float, thickness_m: float) -> list:
    """An L lying flat: an arm ``long_m`` along x and one ``short_m`` along y, ``width_m`` wide."""
    return [_slab(0.0, long_m, 0.0, width_m, thickness_m),
            _slab(0.0, width_m, width_m, short_m, thickness_m)]


def t_block_parts(bar_m: float, stem_m: float, width_m: float, thickness_m: float) -> list:
    """A T lying flat: a bar ``bar_m`` along x and a stem below it, ``stem_m`` total height."""
    half, w2 = bar_m / 2.0, width_m / 2.0
    return [_slab(-half, half, stem_m - width_m, stem_m, thickness_m),
            _slab(-w2, w2, 0.0, stem_m - width_m, thickness_m)]


def cross_block_parts(span_m: float, width_m: float, thickness_m: float) -> list:
    """A plus sign lying flat: a bar along x and two arms along y, ``span_m`` across."""
    half, w2 = span_m / 2.0, width_m / 2.0
    return [_slab(-half, half, -w2, w2, thickness_m),
            _slab(-w2, w2, w2, half, thickness_m),
            _slab(-w2, w2, -half, -w2, thickness_m)]


# ---------------------------------------------------------------- rounded boxes and blobs


def rounded_box_parts(size_x_m: float, size_y_m: float, size_z_m: float, radius_m: float,
                      corner_steps: int = 3) -> list:
    """A box with all edges and corners rounded by ``radius_m``: the hull of eight sphere
    octants (``corner_steps`` + 1 points along each corner arc)."""
    half = np.array([size_x_m, size_y_m, size_z_m]) / 2.0
    if radius_m <= 0.0 or np.any(half <= radius_m):
        raise MeshError(f"rounded box: radius {radius_m} m must be in (0, half the smallest size)")
    t = np.linspace(0.0, np.pi / 2.0, corner_steps + 1)
    polar, azim = np.meshgrid(t, t)
    octant = radius_m * np.column_stack([(np.sin(polar) * np.cos(azim)).ravel(),
                                         (np.sin(polar) * np.sin(azim)).ravel(),
                                         np.cos(polar).ravel()])
    pts = []
    for signs in np.array(np.meshgrid([-1, 1], [-1, 1], [-1, 1])).T.reshape(-1, 3):
        pts.append(signs * (half - radius_m) + signs * octant)
    return [convex_part(np.vstack(pts))]


def blob_parts(semi_axes_m, seed: int, points: int = 48, roughness: float = 0.25) -> list:
    """An irregular convex blob (stone, potato): the hull of ``points`` random directions on an
    ellipsoid of ``semi_axes_m``, each pulled in by up to ``roughness``; seeded, so repeatable."""
    rng = np.random.default_rng(seed)
    dirs = rng.normal(size=(points, 3))
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    scale = 1.0 - roughness * rng.random(points)
    return [resting_on_stable_face(convex_part(dirs * scale[:, None] * np.asarray(semi_axes_m, dtype=float)))]


def resting_on_stable_face(part: trimesh.Trimesh) -> trimesh.Trimesh:
    """``part`` rotated to lie on its most stable face: the face whose plane is nearest to the
    centre of mass (for a convex body the foot of that perpendicular lies in the face, so the
    body rests there without tipping, with its centre of mass as low as possible)."""
    com = part.center_mass
    dist = np.einsum("ij,ij->i", part.triangles[:, 0, :] - com, part.face_normals)
    down = part.face_normals[int(np.argmin(dist))]
    return part.copy().apply_transform(trimesh.geometry.align_vectors(down, [0.0, 0.0, -1.0]))
