"""Where the pads close on the object, for every candidate frame at once (vectorised).

For a frame (approach ``a``, closing axis ``c``, line offset ``x0`` along ``b`` = c × a) the
object's points are read in the frame's coordinates X = p·b, Y = p·c, Z = p·a (Z grows
*into* the object). Then:

* **depth**: the TCP goes as deep as the middle of the object's extent along ``a`` in the
  pads' strip (|X − x0| ≤ the pad's half width), but never so deep that the palm comes
  within ``palm_clearance_m`` of the object's points under it, nor so deep that any part of
  the hand comes within ``table_clearance_m`` of the table;
* **material**: the points in the pads' window (the strip, ±the pads' half length along
  ``a`` around the TCP): at least ``min_material_points``; their span along ``c`` is the
  width to close on (≤ ``max_width_m``), the pads centred on it;
* **contacts**: at each end of that span the material within ``contact_depth_m`` must
  cover at least ``min_contact_fraction`` of the pad's width (an object's corner under a
  pad's edge is no grip); at each end at least ``min_facing_fraction`` of the contact patch
  must face the pad within ``friction_cone_deg`` (its normals — seen, or inferred from the
  solid model; a slanted face squeezed across slips out, a rounded edge above a side wall
  does not), and how well the patch faces it on average is the antipodality;
* **the fingers' way in**: the fingers, opened to width + ``open_margin_m``, sweep along
  ``a`` down to the pads' far edge; at most ``blocked_points`` of the object's points may
  lie in their way (a mug's handle, a wider part above the grasp).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...motion.thin_matmul import thin_matmul
from .candidates import Frames
from .hand_model import HandModel
from .target_model import TargetModel

#: Refusal codes of a frame (the reason strings, in this order, for reports).
OK, NO_MATERIAL, TOO_WIDE, TABLE, EDGE_CONTACT, FINGER_BLOCKED, OUTSIDE_CONE = range(7)
REASONS = ("ok", "no material between the pads", "too wide to close on",
           "the hand would meet the table", "a pad would touch the material only at its edge",
           "a finger blocked by the object itself",
           "a seen contact surface slants out of the friction cone")


@dataclass(frozen=True)
class ContactLimits:
    """The limits of the contact checks (see the module doc), in metres."""

    max_width_m: float
    min_width_m: float
    open_margin_m: float
    max_opening_m: float
    palm_clearance_m: float
    table_clearance_m: float
    min_material_points: int
    contact_depth_m: float
    min_contact_fraction: float
    blocked_points: int
    tolerance_m: float = 0.002
    min_pad_overlap_m: float = 0.012
    friction_cone_deg: float = 35.0
    min_facing_fraction: float = 0.25


@dataclass(frozen=True)
class Contacts:
    """Per frame (K,): ``code`` (:data:`REASONS`), the TCP's depth ``z_tcp`` and the pads'
    centre ``y_mid`` (frame coordinates), ``width_m``, ``opening_m``, ``coverage`` (the
    worse pad's share of its width on material), ``antipodal`` in [0, 1], ``overlap`` (the
    pads' share of their length on material), ``lateral_m`` / ``depth_off_m``: the closing
    line's distance from the object's centroid across and along the approach."""

    code: np.ndarray
    z_tcp: np.ndarray
    y_mid: np.ndarray
    width_m: np.ndarray
    opening_m: np.ndarray
    coverage: np.ndarray
    antipodal: np.ndarray
    overlap: np.ndarray
    lateral_m: np.ndarray
    depth_off_m: np.ndarray

    def tcp_positions(self, frames: Frames) -> np.ndarray:
        """(K, 3) world TCP positions (the grasps' contact points)."""
        return (frames.x0[:, None] * frames.b + self.y_mid[:, None] * frames.c
                + self.z_tcp[:, None] * frames.a)


def concat_contacts(first: Contacts, second: Contacts) -> Contacts:
    """The contacts of ``first`` followed by those of ``second``."""
    from dataclasses import fields

    return Contacts(**{f.name: np.concatenate([getattr(first, f.name), getattr(second, f.name)])
                       for f in fields(Contacts)})


def _masked_min(v: np.ndarray, m: np.ndarray) -> np.ndarray:
    """(K,) the smallest of ``v`` (N, K) where ``m`` holds, per column (inf: none) — as
    ``np.min(v, axis=0, where=m, initial=np.inf)``, whose masked loop is twice as slow: the
    values left out become inf, which no minimum takes (the same values, in the same order)."""
    if len(v) == 0:
        return np.min(v, axis=0, where=m, initial=np.inf)
    return np.where(m, v, np.inf).min(axis=0)


def _masked_max(v: np.ndarray, m: np.ndarray) -> np.ndarray:
    """(K,) the largest of ``v`` (N, K) where ``m`` holds, per column (-inf: none); see
    :func:`_masked_min`."""
    if len(v) == 0:
        return np.max(v, axis=0, where=m, initial=-np.inf)
    return np.where(m, v, -np.inf).max(axis=0)


def _lowest(nb: np.ndarray, nc: np.ndarray, na: np.ndarray, corners: np.ndarray) -> np.ndarray:
    """(K,) the lowest height, relative to the TCP, of the hand ``corners`` (TCP frame) for
    frames whose axes b, c, a have the table-normal components nb, nc, na — the worse of the
    two hand orientations about the approach ((x, y) → (−x, −y))."""
    across = np.abs(np.outer(nb, corners[:, 0]) + np.outer(nc, corners[:, 1]))
    return (np.outer(na, corners[:, 2]) - across).min(axis=1)


def table_bound(frames: Frames, y_mid: np.ndarray, opening: np.ndarray, hand: HandModel,
                plane_n: np.ndarray, plane_c: float, clearance_m: float) -> np.ndarray:
    """(K,) the deepest TCP depth Z at which every hand box corner stays ``clearance_m``
    above the table (inf where the approach does not go down)."""
    n = np.asarray(plane_n, float)
    nb, nc, na = frames.b @ n, frames.c @ n, frames.a @ n
    out = np.full(len(frames), np.inf)
    key = np.round(opening, 3)
    for g in np.unique(key):
        sel = key == g
        low = _lowest(nb[sel], nc[sel], na[sel], hand.boxes.corners(float(g)))
        base = frames.x0[sel] * nb[sel] + y_mid[sel] * nc[sel] + float(plane_c)
        # TCP height + low = base + Z·na + low >= clearance, with na < 0
        with np.errstate(divide="ignore", invalid="ignore"):
            out[sel] = np.where(na[sel] < -1e-9, (clearance_m - low - base) / na[sel], np.inf)
    return out


def _material(X, Y, Z, strip, z_tcp, hand: HandModel):
    """(material mask, y_lo, y_hi, count) in the pads' window at depth ``z_tcp``."""
    mat = strip & (np.abs(Z - z_tcp[None, :]) <= hand.pad_half_length_m)
    return mat, _masked_min(Y, mat), _masked_max(Y, mat), mat.sum(axis=0)


def _coverage(X, Y, mat, y_edge, sign, lim: ContactLimits, hand: HandModel):
    """(K,) the share of the pad's width the material within ``contact_depth_m`` of the
    edge ``y_edge`` covers (``sign`` +1: the upper edge)."""
    d = Y - y_edge[None, :]  # sign · d >= −depth, without the product (negation is exact)
    near = mat & ((d >= -lim.contact_depth_m) if sign > 0 else (d <= lim.contact_depth_m))
    span = _masked_max(X, near) - _masked_min(X, near)
    return np.clip(np.nan_to_num(span, neginf=0.0, posinf=0.0) / (2.0 * hand.pad_half_width_m), 0.0, 1.0), near


def _antipodal(a: np.ndarray, facing: np.ndarray, near: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(mean |n·c|, share of the points facing the pad within the cone) of the points in
    ``near`` per frame, ``a`` (N, K) being |n·c| and ``facing`` (N, K) a >= cos(cone); NaN
    where there are none."""
    cnt = near.sum(axis=0)
    mean = np.where(cnt > 0, np.where(near, a, 0.0).sum(axis=0) / np.maximum(cnt, 1), np.nan)
    inside = np.where(cnt > 0, (near & facing).sum(axis=0) / np.maximum(cnt, 1), np.nan)
    return mean, inside


def _fingers_blocked(dx, Y, Z, y_mid, z_tcp, opening, lim: ContactLimits, hand: HandModel):
    """(K,) object points in the worse finger's way (its sweep along the approach); ``dx``
    (N, K): the points' distances |X − x0| from the closing lines."""
    tol = lim.tolerance_m
    way = (dx <= hand.pad_half_width_m + tol) & (Z <= (z_tcp + hand.pad_half_length_m)[None, :])
    inner = 0.5 * opening[None, :] - tol
    outer = 0.5 * opening[None, :] + hand.finger_thickness_m
    d = Y - y_mid[None, :]  # the upper finger's side; the lower's is −d (negation is exact)
    upper = (way & (d >= inner) & (d <= outer)).sum(axis=0)
    lower = (way & (d <= -inner) & (d >= -outer)).sum(axis=0)
    return np.maximum(upper, lower).astype(np.int64, copy=False)


def _project(points: np.ndarray, frames: Frames):
    """(X, Y, Z) (N, K) float32: the points in every frame's (b, c, a) coordinates, computed
    once per (approach, closing) pair (:mod:`~grasp_pipeline.motion.thin_matmul`) and spread to
    its lines."""
    pairs, first = np.unique(frames.pair, return_index=True)
    axes = np.ascontiguousarray(np.concatenate([frames.b[first], frames.c[first], frames.a[first]]).T,
                                dtype=np.float32)
    proj = thin_matmul(points.astype(np.float32), axes)  # (N, 3 P)
    col = np.searchsorted(pairs, frames.pair)
    n = len(pairs)
    return proj[:, col], proj[:, n + col], proj[:, 2 * n + col]


def _normals_along_closing(normals: np.ndarray, frames: Frames) -> np.ndarray:
    """(N, K) float32 n·c of the points' normals (N, 3) along every frame's closing axis: the
    products of ``normals @ frames.c.T``, computed once per distinct closing axis (frames of
    one pair share it) (:func:`~grasp_pipeline.motion.thin_matmul.thin_matmul`): the same
    products, element by element."""
    pairs, first, col = np.unique(frames.pair, return_index=True, return_inverse=True)
    axes = frames.c[first]
    if not np.array_equal(axes[col.reshape(-1)], frames.c):  # a pair with several closing axes
        axes, col = frames.c, np.arange(len(frames))
    prod = thin_matmul(np.asarray(normals, dtype=float), np.ascontiguousarray(axes.T, dtype=float))
    # C order, as the product was: the sums over the points run in the same order
    return np.take(prod.astype(np.float32), col.reshape(-1), axis=1)


def evaluate(frames: Frames, target: TargetModel, hand: HandModel, lim: ContactLimits,
             plane_n: np.ndarray, plane_c: float, depth_cap=None) -> Contacts:
    """The contact checks of every frame (module doc); ``depth_cap`` (K,): the TCP goes no
    deeper than this (a hand raised to clear a neighbour)."""
    X, Y, Z = _project(target.points, frames)
    x0 = frames.x0
    dx = np.abs(X - x0[None, :])
    strip = dx <= hand.pad_half_width_m
    palm = dx <= hand.pad_half_width_m + 0.025
    z_first, z_last = _masked_min(Z, strip), _masked_max(Z, strip)
    z_palm = _masked_min(Z, palm) + hand.palm_above_tcp_m - lim.palm_clearance_m
    z_tcp = np.minimum(0.5 * (z_first + z_last), z_palm)
    z_tcp = np.where(np.isfinite(z_tcp), z_tcp, 0.0)
    _, y_lo, y_hi, n0 = _material(X, Y, Z, strip, z_tcp, hand)
    y_mid = np.where(n0 > 0, 0.5 * (np.where(n0 > 0, y_lo, 0.0) + np.where(n0 > 0, y_hi, 0.0)), 0.0)
    opening = np.minimum(np.nan_to_num(y_hi - y_lo, posinf=0.0, neginf=0.0) + lim.open_margin_m,
                         lim.max_opening_m)
    z_table = table_bound(frames, y_mid, opening, hand, plane_n, plane_c, lim.table_clearance_m)
    z_tcp = np.minimum(z_tcp, z_table)
    if depth_cap is not None:
        z_tcp = np.minimum(z_tcp, np.asarray(depth_cap, dtype=z_tcp.dtype))
    mat, y_lo, y_hi, count = _material(X, Y, Z, strip, z_tcp, hand)
    width = np.nan_to_num(y_hi - y_lo, posinf=0.0, neginf=0.0)
    y_mid = np.where(count > 0, 0.5 * (np.where(count > 0, y_lo, 0.0) + np.where(count > 0, y_hi, 0.0)), 0.0)
    width = np.maximum(width, lim.min_width_m)
    opening = np.minimum(width + lim.open_margin_m, lim.max_opening_m)
    cov_hi, near_hi = _coverage(X, Y, mat, y_hi, 1.0, lim, hand)
    cov_lo, near_lo = _coverage(X, Y, mat, y_lo, -1.0, lim, hand)
    a_nc = np.abs(_normals_along_closing(target.normals, frames))
    in_cone = a_nc >= float(np.cos(np.radians(lim.friction_cone_deg)))
    (m_hi, f_hi), (m_lo, f_lo) = _antipodal(a_nc, in_cone, near_hi), _antipodal(a_nc, in_cone, near_lo)
    ends, facing = np.stack([m_hi, m_lo]), np.stack([f_hi, f_lo])
    known = np.isfinite(ends)
    outside_cone = np.any(known & (np.nan_to_num(facing) < lim.min_facing_fraction), axis=0)
    anti = np.where(known.any(axis=0), np.where(known, ends, 0.0).sum(axis=0) / np.maximum(known.sum(axis=0), 1), 0.5)
    blocked = _fingers_blocked(dx, Y, Z, y_mid, z_tcp, opening, lim, hand)
    pad_lo, pad_hi = z_tcp - hand.pad_half_length_m, z_tcp + hand.pad_half_length_m
    overlap = np.clip((np.minimum(pad_hi, z_last) - np.maximum(pad_lo, z_first))
                      / (2.0 * hand.pad_half_length_m), 0.0, 1.0)
    overlap = np.nan_to_num(overlap)
    code = np.full(len(frames), OK)
    code[blocked > lim.blocked_points] = FINGER_BLOCKED
    code[outside_cone] = OUTSIDE_CONE
    code[np.minimum(cov_hi, cov_lo) < lim.min_contact_fraction] = EDGE_CONTACT
    code[width > lim.max_width_m] = TOO_WIDE
    code[count < lim.min_material_points] = NO_MATERIAL
    code[z_table < z_first - hand.pad_half_length_m] = TABLE
    code[z_tcp + hand.pad_half_length_m < z_first + lim.min_pad_overlap_m] = NO_MATERIAL
    c = target.centroid
    return Contacts(code, z_tcp, y_mid, width, opening, np.minimum(cov_hi, cov_lo), anti, overlap,
                    np.abs(frames.b @ c - x0), np.abs(frames.a @ c - z_tcp))
