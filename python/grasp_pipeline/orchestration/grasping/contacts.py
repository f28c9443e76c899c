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

from .candidates import Frames
from .hand_model import HandModel
from .pad_passes import EndLimits, PadEnd, passes_for
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


def _coverage(end: PadEnd, hand: HandModel) -> np.ndarray:
    """(K,) the share of the pad's width that the contact patch ``end`` covers along X."""
    span = end.x_hi - end.x_lo
    return np.clip(np.nan_to_num(span, neginf=0.0, posinf=0.0) / (2.0 * hand.pad_half_width_m), 0.0, 1.0)


def _antipodal(end: PadEnd) -> tuple[np.ndarray, np.ndarray]:
    """(mean |n·c|, share of the points facing the pad within the cone) of the patch ``end``
    per frame; NaN where it has no point."""
    cnt = end.count
    mean = np.where(cnt > 0, end.normal_sum / np.maximum(cnt, 1), np.nan)
    inside = np.where(cnt > 0, end.facing / np.maximum(cnt, 1), np.nan)
    return mean, inside


def _pads_centre(y_lo: np.ndarray, y_hi: np.ndarray, count: np.ndarray) -> np.ndarray:
    """(K,) the middle of the material's span along Y (0 where there is no material)."""
    some = count > 0
    return np.where(some, 0.5 * (np.where(some, y_lo, 0.0) + np.where(some, y_hi, 0.0)), 0.0)


def evaluate(frames: Frames, target: TargetModel, hand: HandModel, lim: ContactLimits,
             plane_n: np.ndarray, plane_c: float, depth_cap=None) -> Contacts:
    """The contact checks of every frame (module doc); ``depth_cap`` (K,): the TCP goes no
    deeper than this (a hand raised to clear a neighbour)."""
    passes = passes_for(target, frames, hand)
    z_first, z_last, z_palm = passes.depth_bounds()
    z_palm = z_palm + hand.palm_above_tcp_m - lim.palm_clearance_m
    with np.errstate(invalid="ignore"):  # a strip without points: inf - inf, replaced below
        z_tcp = np.minimum(0.5 * (z_first + z_last), z_palm)
    z_tcp = np.where(np.isfinite(z_tcp), z_tcp, 0.0)
    y_lo, y_hi, n0 = passes.material(z_tcp)
    opening = np.minimum(np.nan_to_num(y_hi - y_lo, posinf=0.0, neginf=0.0) + lim.open_margin_m,
                         lim.max_opening_m)
    z_table = table_bound(frames, _pads_centre(y_lo, y_hi, n0), opening, hand, plane_n, plane_c,
                          lim.table_clearance_m)
    z_tcp = np.minimum(z_tcp, z_table)
    if depth_cap is not None:
        z_tcp = np.minimum(z_tcp, np.asarray(depth_cap, dtype=z_tcp.dtype))
    y_lo, y_hi, count = passes.material(z_tcp)
    width = np.maximum(np.nan_to_num(y_hi - y_lo, posinf=0.0, neginf=0.0), lim.min_width_m)
    y_mid = _pads_centre(y_lo, y_hi, count)
    opening = np.minimum(width + lim.open_margin_m, lim.max_opening_m)
    end_limits = EndLimits(lim.contact_depth_m, float(np.cos(np.radians(lim.friction_cone_deg))),
                           hand.pad_half_width_m + lim.tolerance_m)
    ends = passes.ends(end_limits, z_tcp, y_lo, y_hi, y_mid, 0.5 * opening - lim.tolerance_m,
                       0.5 * opening + hand.finger_thickness_m)
    cov = np.minimum(_coverage(ends.upper, hand), _coverage(ends.lower, hand))
    (m_hi, f_hi), (m_lo, f_lo) = _antipodal(ends.upper), _antipodal(ends.lower)
    sides, facing = np.stack([m_hi, m_lo]), np.stack([f_hi, f_lo])
    known = np.isfinite(sides)
    outside_cone = np.any(known & (np.nan_to_num(facing) < lim.min_facing_fraction), axis=0)
    anti = np.where(known.any(axis=0), np.where(known, sides, 0.0).sum(axis=0) / np.maximum(known.sum(axis=0), 1), 0.5)
    blocked = np.maximum(ends.blocked_upper, ends.blocked_lower)
    pad_lo, pad_hi = z_tcp - hand.pad_half_length_m, z_tcp + hand.pad_half_length_m
    overlap = np.clip((np.minimum(pad_hi, z_last) - np.maximum(pad_lo, z_first))
                      / (2.0 * hand.pad_half_length_m), 0.0, 1.0)
    overlap = np.nan_to_num(overlap)
    code = np.full(len(frames), OK)
    code[blocked > lim.blocked_points] = FINGER_BLOCKED
    code[outside_cone] = OUTSIDE_CONE
    code[cov < lim.min_contact_fraction] = EDGE_CONTACT
    code[width > lim.max_width_m] = TOO_WIDE
    code[count < lim.min_material_points] = NO_MATERIAL
    code[z_table < z_first - hand.pad_half_length_m] = TABLE
    code[z_tcp + hand.pad_half_length_m < z_first + lim.min_pad_overlap_m] = NO_MATERIAL
    c = target.centroid
    return Contacts(code, z_tcp, y_mid, width, opening, cov, anti, overlap,
                    np.abs(frames.b @ c - frames.x0), np.abs(frames.a @ c - z_tcp))
