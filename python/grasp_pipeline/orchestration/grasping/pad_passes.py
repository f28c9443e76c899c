"""The passes over an object's points that the contact checks (:mod:`.contacts`) make for every
candidate frame: per frame a reduction over the points (minima, maxima, counts, one float32 sum).

Two implementations give the same values bit for bit:

* :class:`CorePasses` — the C++ core (``_core.pad_depth_bounds``, ``pad_material``,
  ``pad_contact_ends``): one loop per frame over the points, in the operand types of the numpy
  formulation; the path of two frames or more;
* :class:`NumpyPasses` — the numpy formulation on (N, K) arrays: the reference of the tests and
  the path of a single frame, whose float32 sum numpy takes pairwise (over one column) where
  the core adds in the points' order (as numpy does over the columns of two frames or more).

The points are read in each frame's coordinates X = p·b, Y = p·c, Z = p·a, computed once per
distinct (approach, closing) pair (:func:`pair_products`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ... import _core
from ...motion.thin_matmul import thin_matmul
from .candidates import Frames
from .hand_model import HandModel
from .target_model import TargetModel


@dataclass(frozen=True)
class PadEnd:
    """The contact patch at one end of the material, per frame (K,): the smallest and largest
    X of its points, the float32 sum of their |n·c|, their count and how many face the pad."""

    x_lo: np.ndarray
    x_hi: np.ndarray
    normal_sum: np.ndarray
    count: np.ndarray
    facing: np.ndarray


@dataclass(frozen=True)
class PadEnds:
    """The patches at the material's upper and lower ends and the object's points in each
    finger's way (K,) int64."""

    upper: PadEnd
    lower: PadEnd
    blocked_upper: np.ndarray
    blocked_lower: np.ndarray


@dataclass(frozen=True)
class EndLimits:
    """The limits of :meth:`CorePasses.ends` / :meth:`NumpyPasses.ends` [m]; ``cos_cone``: a
    normal faces the pad where |n·c| >= it."""

    contact_depth_m: float
    cos_cone: float
    finger_half_width_m: float


def masked_min(v: np.ndarray, m: np.ndarray) -> np.ndarray:
    """(K,) the smallest of ``v`` (N, K) where ``m`` holds, per column (inf: none) — as
    ``np.min(v, axis=0, where=m, initial=np.inf)``, whose masked loop is twice as slow: the
    values left out become inf, which no minimum takes (the same values, in the same order)."""
    if len(v) == 0:
        return np.min(v, axis=0, where=m, initial=np.inf)
    return np.where(m, v, np.inf).min(axis=0)


def masked_max(v: np.ndarray, m: np.ndarray) -> np.ndarray:
    """(K,) the largest of ``v`` (N, K) where ``m`` holds, per column (-inf: none); see
    :func:`masked_min`."""
    if len(v) == 0:
        return np.max(v, axis=0, where=m, initial=-np.inf)
    return np.where(m, v, -np.inf).max(axis=0)


def pair_products(points: np.ndarray, frames: Frames) -> tuple[np.ndarray, np.ndarray, int]:
    """(proj (N, 3 P) float32, column (K,) int64, P): the points times the b, c and a axes of
    the P distinct (approach, closing) pairs (:mod:`~grasp_pipeline.motion.thin_matmul`), and
    the pair of each frame (X of frame k is ``proj[:, column[k]]``, Y ``proj[:, P + column[k]]``,
    Z ``proj[:, 2 P + column[k]]``)."""
    pairs, first = np.unique(frames.pair, return_index=True)
    axes = np.ascontiguousarray(np.concatenate([frames.b[first], frames.c[first], frames.a[first]]).T,
                                dtype=np.float32)
    proj = thin_matmul(points.astype(np.float32), axes)  # (N, 3 P)
    return proj, np.searchsorted(pairs, frames.pair).astype(np.int64), len(pairs)


def project(points: np.ndarray, frames: Frames):
    """(X, Y, Z) (N, K) float32: the points in every frame's (b, c, a) coordinates
    (:func:`pair_products` spread to the frames)."""
    proj, col, n = pair_products(points, frames)
    return proj[:, col], proj[:, n + col], proj[:, 2 * n + col]


def closing_products(normals: np.ndarray, frames: Frames) -> tuple[np.ndarray, np.ndarray]:
    """(prod (N, Q) float32, column (K,) int64): n·c of the points' normals (N, 3) along each
    distinct closing axis (frames of one pair share it) and each frame's axis (a fixed-order
    float64 product, :func:`~grasp_pipeline.motion.thin_matmul.thin_matmul`, rounded to
    float32: the products of ``normals @ frames.c.T``, element by element)."""
    _, first, col = np.unique(frames.pair, return_index=True, return_inverse=True)
    axes = frames.c[first]
    col = col.reshape(-1)
    if not np.array_equal(axes[col], frames.c):  # a pair with several closing axes
        axes, col = frames.c, np.arange(len(frames))
    prod = thin_matmul(np.asarray(normals, dtype=float), np.ascontiguousarray(axes.T, dtype=float))
    return prod.astype(np.float32), col.astype(np.int64)


def normals_along_closing(normals: np.ndarray, frames: Frames) -> np.ndarray:
    """(N, K) float32 n·c of the points' normals along every frame's closing axis
    (:func:`closing_products` spread to the frames, C order)."""
    prod, col = closing_products(normals, frames)
    return np.take(prod, col, axis=1)


def fingers_blocked(dx, Y, Z, y_mid, z_tcp, inner, outer, finger_half_width_m):
    """(upper, lower) (K,) int64: object points in each finger's way — within
    ``finger_half_width_m`` of the closing line (``dx`` (N, K) = |X − x0|), no deeper than the
    pads' far edge ``z_tcp`` (the TCP's depth plus the pads' half length, float64) and
    d = Y − y_mid within ``inner``..``outer`` (the upper finger) or −outer..−inner."""
    way = (dx <= finger_half_width_m) & (Z <= z_tcp[None, :])
    d = Y - y_mid[None, :]  # the upper finger's side; the lower's is −d (negation is exact)
    upper = (way & (d >= inner[None, :]) & (d <= outer[None, :])).sum(axis=0)
    lower = (way & (d <= -inner[None, :]) & (d >= -outer[None, :])).sum(axis=0)
    return upper.astype(np.int64, copy=False), lower.astype(np.int64, copy=False)


def patch_near(Y, mat, y_edge, sign: float, contact_depth_m: float) -> np.ndarray:
    """(N, K) the material within ``contact_depth_m`` of the edge ``y_edge`` (``sign`` +1: the
    upper edge): ``sign · (Y − edge) >= −depth``, without the product (negation is exact)."""
    d = Y - y_edge[None, :]
    return mat & ((d >= -contact_depth_m) if sign > 0 else (d <= contact_depth_m))


class NumpyPasses:
    """The passes on (N, K) float32 arrays of the points in every frame (see the module doc)."""

    def __init__(self, target: TargetModel, frames: Frames, hand: HandModel) -> None:
        self.X, self.Y, self.Z = project(target.points, frames)
        self.dx = np.abs(self.X - frames.x0[None, :])
        self.strip = self.dx <= hand.pad_half_width_m
        self.hand, self.target, self.frames = hand, target, frames

    def depth_bounds(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(z_first, z_last, z_palm): see :func:`CorePasses.depth_bounds`."""
        palm = self.dx <= self.hand.pad_half_width_m + 0.025
        return masked_min(self.Z, self.strip), masked_max(self.Z, self.strip), masked_min(self.Z, palm)

    def _mat(self, z_tcp: np.ndarray) -> np.ndarray:
        return self.strip & (np.abs(self.Z - z_tcp[None, :]) <= self.hand.pad_half_length_m)

    def material(self, z_tcp: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(y_lo, y_hi, count): see :func:`CorePasses.material`."""
        mat = self._mat(z_tcp)
        return masked_min(self.Y, mat), masked_max(self.Y, mat), mat.sum(axis=0)

    def ends(self, lim: EndLimits, z_tcp, y_lo, y_hi, y_mid, inner, outer) -> PadEnds:
        """See :func:`CorePasses.ends`."""
        mat = self._mat(z_tcp)
        a_nc = np.abs(normals_along_closing(self.target.normals, self.frames))
        facing = a_nc >= lim.cos_cone
        sides = []
        for edge, sign in ((y_hi, 1.0), (y_lo, -1.0)):
            near = patch_near(self.Y, mat, edge, sign, lim.contact_depth_m)
            sides.append(PadEnd(masked_min(self.X, near), masked_max(self.X, near),
                                np.where(near, a_nc, 0.0).sum(axis=0), near.sum(axis=0),
                                (near & facing).sum(axis=0)))
        up, low = fingers_blocked(self.dx, self.Y, self.Z, y_mid, z_tcp + self.hand.pad_half_length_m,
                                  inner, outer, lim.finger_half_width_m)
        return PadEnds(sides[0], sides[1], up, low)


class CorePasses:
    """The passes in the C++ core, one loop per frame over the points (see the module doc)."""

    def __init__(self, target: TargetModel, frames: Frames, hand: HandModel) -> None:
        proj, self.column, n = pair_products(target.points, frames)
        self.xyz = np.ascontiguousarray(proj.T).reshape(3, n, len(proj))
        self.x0 = np.ascontiguousarray(frames.x0, dtype=np.float64)
        self.hand, self.target, self.frames = hand, target, frames

    def depth_bounds(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(z_first, z_last, z_palm) float32 (K,): the smallest and largest Z in the pads' strip
        (|X − x0| <= the pads' half width) and the smallest in the palm's (25 mm wider)."""
        h = self.hand
        return _core.pad_depth_bounds(self.xyz, self.column, self.x0, h.pad_half_width_m,
                                      h.pad_half_width_m + 0.025)

    def material(self, z_tcp: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(y_lo, y_hi float32, count int64) (K,) of the material: the points in the pads' strip
        within the pads' half length of ``z_tcp`` (float32 or float64: compared in its type)."""
        return _core.pad_material(self.xyz, self.column, self.x0, self.hand.pad_half_width_m,
                                  z_tcp, self.hand.pad_half_length_m)

    def ends(self, lim: EndLimits, z_tcp, y_lo, y_hi, y_mid, inner, outer) -> PadEnds:
        """The contact patches at the material's ends (at ``z_tcp``, float64, running
        ``y_lo``..``y_hi``) and the points in the fingers' way (:func:`fingers_blocked`)."""
        closing, column = closing_products(self.target.normals, self.frames)
        out = _core.pad_contact_ends(self.xyz, self.column, self.x0, np.ascontiguousarray(np.abs(closing).T),
                                     column, z_tcp, y_lo, y_hi, y_mid, inner, outer,
                                     self.hand.pad_half_width_m, self.hand.pad_half_length_m,
                                     lim.contact_depth_m, lim.cos_cone, lim.finger_half_width_m)
        return PadEnds(PadEnd(**out["upper"]), PadEnd(**out["lower"]), out["blocked_upper"],
                       out["blocked_lower"])


def passes_for(target: TargetModel, frames: Frames, hand: HandModel) -> NumpyPasses | CorePasses:
    """The core's passes for two frames or more of an object with points, else numpy's."""
    if len(frames) > 1 and len(target.points) > 0:
        return CorePasses(target, frames, hand)
    return NumpyPasses(target, frames, hand)
