"""Candidate hand frames of the any-side sampler: approach directions × rotations about the
approach × lines across the object.

* **approaches**: the table's downward normal (top-down), then rings tilted by each of
  ``tilts_deg`` from it at ``azimuths`` evenly spaced directions, plus, on every ring, the
  direction leaning away from the robot's base (the way the arm reaches most easily);
* **closing axes**: for each approach, ``rotations`` axes evenly spaced over 180° about it
  (a parallel gripper's closing axis has no sign), plus, for contact pairs, the seen points'
  normals made orthogonal to the approach (antipodal candidates: the closing axis along the
  surface normal at a sampled point);
* **lines**: for each (approach, closing axis) pair, lines across the object at the
  projection of its centroid and every ``line_spacing_m`` on both sides of it.

Top-down grasps are the tilt-0 special case of the same sampler.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Frames:
    """K candidate frames: ``a`` approach (into the object), ``c`` closing axis, ``b`` = c × a
    (the TCP x axis), each (K, 3) unit; ``x0`` (K,) the line's offset along b [m] (a
    world-projection coordinate: the line is the points whose b-projection is x0);
    ``tilt_deg`` (K,) of the approach from the table normal; ``pair`` (K,) index of the
    (approach, closing) pair."""

    a: np.ndarray
    c: np.ndarray
    b: np.ndarray
    x0: np.ndarray
    tilt_deg: np.ndarray
    pair: np.ndarray

    def __len__(self) -> int:
        return len(self.x0)

    def take(self, idx) -> "Frames":
        return Frames(self.a[idx], self.c[idx], self.b[idx], self.x0[idx], self.tilt_deg[idx],
                      self.pair[idx])


def concat_frames(first: Frames, second: Frames) -> Frames:
    """The frames of ``first`` followed by those of ``second``."""
    return Frames(*(np.concatenate([getattr(first, f), getattr(second, f)])
                    for f in ("a", "c", "b", "x0", "tilt_deg", "pair")))


def plane_basis(n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors orthogonal to ``n`` and to each other (deterministic)."""
    helper = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(n, helper)
    u /= np.linalg.norm(u)
    return u, np.cross(n, u)


def approach_directions(plane_n, tilts_deg, azimuths: int, away_from: np.ndarray | None = None
                        ) -> tuple[np.ndarray, np.ndarray]:
    """(A, 3) unit approach directions (into the object) and their tilts [deg]: straight down
    the table normal ``plane_n`` and, per tilt, ``azimuths`` directions plus the one whose
    horizontal part points from ``away_from`` (the robot base, (2,) or (3,)) to the object
    side — i.e. the hand coming from the robot's side."""
    n = np.asarray(plane_n, dtype=float)
    n = n / np.linalg.norm(n)
    u, v = plane_basis(n)
    dirs, tilts = [-n], [0.0]
    for t in tilts_deg:
        if t <= 0:
            continue
        t_rad = np.radians(float(t))
        phis = list(2.0 * np.pi * np.arange(azimuths) / max(azimuths, 1))
        if away_from is not None:
            d = np.asarray(away_from, float)[:2]
            h = np.array([d[0], d[1], 0.0]) - float(np.array([d[0], d[1], 0.0]) @ n) * n
            if np.linalg.norm(h) > 1e-9:
                phis.append(float(np.arctan2(h @ v, h @ u)))
        for phi in phis:
            horiz = np.cos(phi) * u + np.sin(phi) * v
            dirs.append(-np.cos(t_rad) * n + np.sin(t_rad) * horiz)
            tilts.append(float(t))
    return np.array(dirs), np.array(tilts)


def closing_axes(a: np.ndarray, rotations: int) -> np.ndarray:
    """(rotations, 3) unit closing axes orthogonal to ``a``, evenly spaced over 180°."""
    u, v = plane_basis(np.asarray(a, dtype=float))
    phi = np.pi * np.arange(rotations) / rotations
    return np.outer(np.cos(phi), u) + np.outer(np.sin(phi), v)


def normal_axes(a: np.ndarray, normals: np.ndarray, min_norm: float = 0.5) -> np.ndarray:
    """The seen points' ``normals`` made orthogonal to ``a`` and normalised; those mostly
    along ``a`` (less than ``min_norm`` left) are dropped."""
    c = normals - np.outer(normals @ a, a)
    norm = np.linalg.norm(c, axis=1)
    keep = norm >= min_norm
    return c[keep] / norm[keep, None]


def dominant_normals(normals: np.ndarray, count: int, min_share: float = 0.03) -> np.ndarray:
    """Up to ``count`` dominant directions of ``normals`` (sign ignored: a closing axis has
    none): each normal joins the nearest of 13 fixed directions (faces, edges and corners of
    a cube, one per ± pair); the mean of every group holding at least ``min_share`` of them,
    largest first."""
    n = np.asarray(normals, dtype=float).reshape(-1, 3)
    if len(n) == 0 or count <= 0:
        return np.zeros((0, 3))
    dirs = np.array([d for d in np.ndindex(3, 3, 3) if d != (1, 1, 1)], float) - 1.0
    dirs = dirs[[tuple(d) > tuple(-d) for d in dirs]]
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    dots = n @ dirs.T
    group = np.argmax(np.abs(dots), axis=1)
    signs = np.sign(dots[np.arange(len(n)), group])[:, None]
    out = []
    for g in np.argsort(-np.bincount(group, minlength=len(dirs))):
        members = group == g
        if members.sum() < max(1, min_share * len(n)) or len(out) >= count:
            break
        m = (signs[members] * n[members]).mean(axis=0)
        if np.linalg.norm(m) > 1e-9:
            out.append(m / np.linalg.norm(m))
    return np.array(out).reshape(-1, 3)


def approaches_across(axes: np.ndarray, plane_n, max_tilt_deg: float, turns_deg=(0.0, 25.0, -25.0, 50.0, -50.0)
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Antipodal candidates: for each closing axis in ``axes`` (a surface normal), the
    approaches orthogonal to it — the most downward one, turned about the axis by each of
    ``turns_deg`` — within ``max_tilt_deg`` of the table normal. Returns (approaches (M, 3),
    their tilts [deg], their closing axes (M, 3))."""
    n = np.asarray(plane_n, dtype=float)
    n = n / np.linalg.norm(n)
    A, T, C = [], [], []
    for c in np.asarray(axes, dtype=float).reshape(-1, 3):
        down = -n - float(-n @ c) * c
        if np.linalg.norm(down) < 1e-6:
            continue
        down /= np.linalg.norm(down)
        side = np.cross(c, down)
        for t in np.radians(turns_deg):
            a = np.cos(t) * down + np.sin(t) * side
            tilt = float(np.degrees(np.arccos(np.clip(-(a @ n), -1.0, 1.0))))
            if tilt <= max_tilt_deg + 1e-9:
                A.append(a)
                T.append(tilt)
                C.append(c)
    if not A:
        return np.zeros((0, 3)), np.zeros(0), np.zeros((0, 3))
    return np.array(A), np.array(T), np.array(C)


def line_offsets(lo: np.ndarray, hi: np.ndarray, centre: np.ndarray, step_m: float,
                 count: int) -> tuple[np.ndarray, np.ndarray]:
    """Offsets along b of the lines across the object, per (approach, closing) pair: the
    centroid's projection ``centre`` (P,) clipped to the object's span [``lo``, ``hi``], then
    ±step, ±2 step, … within the span, at most ``count``. Returns (pair index, offset)."""
    centre = np.clip(centre, lo, hi)
    ks = [0]
    for k in range(1, count):
        ks.append((k + 1) // 2 * (1 if k % 2 else -1))
    offs = centre[:, None] + step_m * np.asarray(ks, float)[None, :]
    inside = (offs >= lo[:, None] - 1e-12) & (offs <= hi[:, None] + 1e-12)
    pair, col = np.nonzero(inside)
    return pair, offs[pair, col]


def build_frames(points: np.ndarray, centroid: np.ndarray, approaches: np.ndarray,
                 tilts: np.ndarray, axes_per_approach: list, step_m: float, lines: int) -> Frames:
    """Every (approach, closing axis, line) frame for the object ``points`` (N, 3)."""
    counts = [len(ax) for ax in axes_per_approach]
    if sum(counts) == 0:
        z = np.zeros((0, 3))
        return Frames(z, z, z, np.zeros(0), np.zeros(0), np.zeros(0, int))
    a = np.repeat(approaches, counts, axis=0)
    c = np.vstack([ax for ax in axes_per_approach if len(ax)])
    t = np.repeat(tilts, counts)
    b = np.cross(c, a)
    x = points @ b.T  # (N, P)
    pair, x0 = line_offsets(x.min(axis=0), x.max(axis=0), b @ centroid, step_m, lines)
    return Frames(a[pair], c[pair], b[pair], x0, t[pair], pair)
