"""Synthetic point clouds for the method tests of the perception core.

Every generator is deterministic (an explicit seed) and returns float64 (N, 3) arrays in
`world` (z up). Noise is Gaussian along z (a depth camera looking down), σ = 2 mm unless
stated — method.md §2.7's `depth_noise_sigma`.
"""

from __future__ import annotations

import numpy as np

SIGMA = 0.002  # depth noise [m]
TABLE_Z = 0.2


def rng_of(seed: int) -> np.random.Generator:
    return np.random.default_rng(seed)


def horizontal_patch(n, x, y, z, sigma=SIGMA, seed=0):
    """n points uniform over the rectangle x=(x0, x1), y=(y0, y1) at height z (+ z noise)."""
    r = rng_of(seed)
    return np.column_stack([r.uniform(x[0], x[1], n), r.uniform(y[0], y[1], n),
                            z + r.normal(0.0, sigma, n)])


def tilted_patch(n, x, y, z0, tilt_deg, sigma=SIGMA, seed=0):
    """A patch whose height rises along +x with slope tan(tilt) from z0 at its centre."""
    p = horizontal_patch(n, x, y, 0.0, sigma, seed)
    xc = 0.5 * (x[0] + x[1])
    p[:, 2] += z0 + np.tan(np.radians(tilt_deg)) * (p[:, 0] - xc)
    return p


def rotation_z(yaw_rad: float) -> np.ndarray:
    c, s = np.cos(yaw_rad), np.sin(yaw_rad)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def box_top(center_xy, size_xy, top_z, yaw_rad=0.0, n=2500, sigma=SIGMA, seed=0):
    """Only the top face of a box (what a camera directly above sees)."""
    r = rng_of(seed)
    loc = np.column_stack([r.uniform(-size_xy[0] / 2, size_xy[0] / 2, n),
                           r.uniform(-size_xy[1] / 2, size_xy[1] / 2, n),
                           np.zeros(n)])
    p = loc @ rotation_z(yaw_rad).T
    p[:, 0] += center_xy[0]
    p[:, 1] += center_xy[1]
    p[:, 2] = top_z + r.normal(0.0, sigma, n)
    return p


def box_surface(center_xy, size, base_z=TABLE_Z, yaw_rad=0.0, n_top=2500, n_side=800,
                sides=(0, 1, 2, 3), sigma=SIGMA, side_sigma=0.0002, seed=0):
    """Top face plus the chosen vertical side faces of a box resting at base_z.

    size = (sx, sy, h) before the yaw; side k is the face at local +x, +y, -x, -y (k=0..3).
    The top carries noise along z (sigma); side points along the face normal (side_sigma: a
    camera looking down at a steep angle sees the sides' depth noise mostly as vertical).
    """
    r = rng_of(seed)
    sx, sy, h = size
    parts = [np.column_stack([r.uniform(-sx / 2, sx / 2, n_top), r.uniform(-sy / 2, sy / 2, n_top),
                              h + r.normal(0.0, sigma, n_top)])]
    for k in sides:
        half_len = sy / 2 if k in (0, 2) else sx / 2
        off = (sx / 2 if k in (0, 2) else sy / 2) * (1 if k in (0, 1) else -1)
        t = r.uniform(-half_len, half_len, n_side)
        z = r.uniform(0.0, h, n_side)
        nrm = off + r.normal(0.0, side_sigma, n_side)
        face = np.column_stack([nrm, t, z]) if k in (0, 2) else np.column_stack([t, nrm, z])
        parts.append(face)
    loc = np.vstack(parts)
    p = loc @ rotation_z(yaw_rad).T
    p[:, 0] += center_xy[0]
    p[:, 1] += center_xy[1]
    p[:, 2] += base_z
    return p


def disc_top(center_xy, diameter, top_z, n=2500, sigma=SIGMA, seed=0):
    """Top face of an upright cylinder."""
    r = rng_of(seed)
    rad = diameter / 2 * np.sqrt(r.uniform(0, 1, n))
    ang = r.uniform(0, 2 * np.pi, n)
    return np.column_stack([center_xy[0] + rad * np.cos(ang), center_xy[1] + rad * np.sin(ang),
                            top_z + r.normal(0.0, sigma, n)])


def table_floor_pseudo_scene(seed=0):
    """method.md §1.3's measured situation, reproduced.

    - table at z = 0.200: 20 072 points,
    - floor at z = 0 (seen past the table edge): 7 275 points,
    - a pseudo-plane 10 cm ABOVE the table (the top of a large object, tilted 6° — within
      the 10° tilt limit, so only dominance can reject it): 2 110 points.
    Returns (points, dict of the true counts and heights).
    """
    table = horizontal_patch(20072, (0.30, 0.90), (-0.40, 0.40), TABLE_Z, seed=seed)
    floor = horizontal_patch(7275, (0.95, 1.40), (-0.60, 0.60), 0.0, seed=seed + 1)
    pseudo = tilted_patch(2110, (0.55, 0.70), (-0.07, 0.07), TABLE_Z + 0.10, 6.0, seed=seed + 2)
    pts = np.vstack([table, floor, pseudo])
    truth = dict(table=20072, floor=7275, pseudo=2110, table_z=TABLE_Z, floor_z=0.0,
                 pseudo_z=TABLE_Z + 0.10)
    return pts, truth


def tabletop_with_cubes(centres=((0.50, -0.08), (0.62, 0.10)), side=0.05, yaw_rad=0.3,
                        table_n=12000, table_z=TABLE_Z, seed=0):
    """A table patch plus 5 cm cubes (top and all four sides) resting on it."""
    parts = [horizontal_patch(table_n, (0.30, 0.85), (-0.30, 0.30), table_z, seed=seed)]
    for k, c in enumerate(centres):
        parts.append(box_surface(c, (side, side, side), base_z=table_z, yaw_rad=yaw_rad,
                                 n_top=900, n_side=300, seed=seed + 10 + k))
    return np.vstack(parts)
