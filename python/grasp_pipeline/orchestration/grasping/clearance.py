"""The whole hand against everything that is not the target, along the approach.

What the planner will check, checked first so no candidate goes to planning that the planner
must refuse: the planner's hand spheres (opened to the grasp's opening, both hand
orientations about the approach) at the grasp and at poses back along the approach up to the
pre-grasp, kept the planner's collision margin clear of

* the neighbours as the planner models them — their column cells (what was seen of them,
  extended down to the table) and the boxes of those not seen well enough (never cleared,
  also at the grasp);
* environment points above the table band and objects no track took — except, for the poses
  near the grasp, inside the target's box grown by the planner's cleared padding (the planner
  lets the hand in there during the final approach);
* the table plane, for spheres outside that cleared region.

Separately, the hand's own boxes other than the fingers (palm, camera) must not touch the
target's points at the grasp (the fingers' way in is :mod:`.contacts`' check).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from ...motion.occupancy import OrientedBox
from .hand_model import HandModel


@dataclass(frozen=True)
class ObstacleSet:
    """Points the hand keeps clear of, each group with its slack (margin + rounding) [m]:
    ``fixed`` (neighbour columns, never cleared), ``clearable`` (environment above the band,
    untracked clusters), the neighbours' ``boxes`` (kept ``box_slack_m`` clear), the table
    (``plane_n``, ``plane_c``), the ``cleared`` region (the target's grown box) and the
    planner's ``margin_m``."""

    fixed: np.ndarray
    fixed_slack_m: float
    clearable: np.ndarray
    clearable_slack_m: float
    boxes: tuple
    box_slack_m: float
    plane_n: np.ndarray
    plane_c: float
    cleared: OrientedBox
    margin_m: float

    def trees(self):
        """KD-trees of ``fixed`` and ``clearable`` (built once)."""
        cached = self.__dict__.get("_trees")
        if cached is None:
            cached = (cKDTree(self.fixed) if len(self.fixed) else None,
                      cKDTree(self.clearable) if len(self.clearable) else None)
            object.__setattr__(self, "_trees", cached)
        return cached


def _query(tree, pts: np.ndarray, reach_m: float) -> np.ndarray:
    if tree is None or len(pts) == 0:
        return np.full(len(pts), np.inf)
    d, _ = tree.query(pts, distance_upper_bound=reach_m)
    return d


def sphere_slack(obs: ObstacleSet, trees, centres: np.ndarray, radii: np.ndarray,
                 near_grasp: bool) -> np.ndarray:
    """(Q,) the smallest slack of spheres (``centres`` (Q, 3), ``radii`` (Q,)) from the
    obstacles (< 0: inside a clearance); ``near_grasp``: the cleared region applies."""
    reach = float(radii.max()) + obs.margin_m + 0.02
    fixed_t, clear_t = trees
    slack = _query(fixed_t, centres, reach) - radii - obs.fixed_slack_m
    d_env = _query(clear_t, centres, reach) - radii - obs.clearable_slack_m
    h = centres @ obs.plane_n + obs.plane_c - radii - obs.margin_m
    if near_grasp:
        inside = obs.cleared.contains(centres)
        d_env = np.where(inside, np.inf, d_env)
        h = np.where(inside, np.inf, h)
    slack = np.minimum(slack, np.minimum(d_env, h))
    for box in obs.boxes:
        slack = np.minimum(slack, box.distance_m(centres) - radii - obs.box_slack_m)
    return slack


def tcp_rotations(a: np.ndarray, c: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(K, 3, 3) TCP rotations (x = c × a, y = c, z = a) of both hand orientations."""
    x = np.cross(c, a)
    R1 = np.stack([x, c, a], axis=2)
    R2 = np.stack([-x, -c, a], axis=2)
    return R1, R2


def hand_slack(obs: ObstacleSet, hand: HandModel, origins: np.ndarray, a: np.ndarray,
               c: np.ndarray, opening: np.ndarray, backs_m) -> np.ndarray:
    """(K, 2) the smallest slack of the hand spheres over the approach poses (``backs_m``
    back along the approach from the grasp ``origins``), per hand orientation."""
    k, s = len(origins), len(hand.spheres.radii)
    if k == 0:
        return np.zeros((0, 2))
    trees = obs.trees()
    local = hand.spheres.centres_closed[None] + opening[:, None, None] * hand.spheres.per_opening[None]
    out = np.empty((k, 2))
    backs = np.asarray(backs_m, dtype=float)
    for side, R in enumerate(tcp_rotations(a, c)):
        rel = np.einsum("kij,ksj->ksi", R, local)  # (K, S, 3)
        pts = origins[:, None, None, :] - backs[None, :, None, None] * a[:, None, None, :] \
            + rel[:, None, :, :]  # (K, B, S, 3)
        rad = np.broadcast_to(hand.spheres.radii, (k, len(backs), s))
        near = np.broadcast_to((backs < 0.06)[None, :, None], (k, len(backs), s))
        flat_p, flat_r, flat_n = pts.reshape(-1, 3), rad.reshape(-1), near.reshape(-1)
        sl = np.empty(len(flat_p))
        sl[flat_n] = sphere_slack(obs, trees, flat_p[flat_n], flat_r[flat_n], True)
        sl[~flat_n] = sphere_slack(obs, trees, flat_p[~flat_n], flat_r[~flat_n], False)
        out[:, side] = sl.reshape(k, -1).min(axis=1)
    return out


def palm_touches_target(hand: HandModel, target_pts: np.ndarray, origins: np.ndarray,
                        a: np.ndarray, c: np.ndarray, opening: np.ndarray, tol_m: float) -> np.ndarray:
    """(K, 2) True where a non-finger box of the hand (palm, camera) at the grasp holds a point
    of the target (grown by ``tol_m``), per hand orientation. The palm's boxes do not move
    with the opening."""
    boxes = hand.boxes
    sel = ~boxes.finger
    centres, Rb, half = boxes.centre_closed[sel], boxes.R[sel], boxes.half[sel] + tol_m
    out = np.zeros((len(origins), 2), dtype=bool)
    rel = target_pts[None, :, :] - origins[:, None, :]  # (K, N, 3)
    for side, R in enumerate(tcp_rotations(a, c)):
        local = np.einsum("kni,kij->knj", rel, R)  # TCP-frame coordinates
        for cen, Rg, h in zip(centres, Rb, half):
            q = np.abs((local - cen) @ Rg)
            inside = q[..., 0] <= h[0]  # axis by axis: np.all over the last axis is slow
            inside &= q[..., 1] <= h[1]
            inside &= q[..., 2] <= h[2]
            out[:, side] |= np.any(inside, axis=1)
    return out
