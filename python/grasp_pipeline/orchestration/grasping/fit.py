"""Top-down grasps fitted to the perceived points, not only to the box (ours; extends method.md §3).

method.md §3 closes across the box's narrow side through the box centre. For an L, T or cross block,
a prism or a mug the box centre may lie beside the material, and in clutter a finger's path may
be taken by a neighbour although the box model of the scene says otherwise. Here every
candidate *closing line* is checked on the points of the scene
(:class:`~grasp_pipeline.orchestration.scene.scene_cloud.SceneCloud`, world frame), in the
line's own frame (``c`` along the closing axis, ``a`` across it, ``h`` above the table):

* **lines**: both box axes as closing axis; on each, lines every ``line_step_m`` across the
  object (contact points shifted along the box), plus the line through the points' centroid;
  at the contact height of :func:`contact_height_m` and, for an object whose lowest visible
  point is high (lying on another), also half-way between that point and its top, and just
  above each lower step of its top surface (:func:`surface_levels`: the upper box of a stack
  that segmentation merged into one cluster is grasped alone);
* **material**: the object's own points in the pads' strip (``|a - a0| ≤ finger_width / 2``)
  above the pads' lowest point — at least ``min_material_points`` of them; their span along
  ``c`` — clipped to the tracked box, whose NADIR measurement bounds the object better than
  an oblique frame's smeared edges (8–9 mm wider on far objects) — is the width to close on
  (the pads are centred on it), which must be at most the request's ``max_width_m``, the usable
  opening (:func:`~.opening.max_grasp_width_m`: the opening less ``min_open_margin_m``; the
  fingers open to width + ``open_margin_m``, at most the gripper's opening: a 68 mm mug is
  grasped with 6 mm to spare on each side);
  at each end the material within ``contact_depth_m`` of it must span at least
  ``min_contact_fraction`` of the pad's width (an L's arm end under a pad's corner is no grip);
* **the planner's view**: the planner models the neighbours as boxes, kept its collision
  margin away in 3-D (above their tops too), and the hand as spheres; the hand's spheres,
  coming straight down to the grasp, must stay that clear of the neighbours' boxes (sampled
  top faces, each sample also by its sampling slack) — else the contact is raised (while the pads still
  overlap the object) or the line is dropped, so no candidate goes to planning that the
  planner must refuse;
* **free descent**: each finger's column (``finger_thickness`` × ``finger_width``, at
  ``open_margin / 2`` outside the material, from the pads' lowest point up) may hold at most
  ``blocked_points`` points of anything — this object, its neighbours, untracked clusters,
  environment above the table band (the table itself is the plane the contact height keeps the
  pads above);
* **rank**: free lines with a clearance (the horizontal distance from the finger columns to
  the nearest point) of at least ``clearance_enough_m`` first, then nearest the centroid of
  the object's area seen from above (:func:`footprint_centroid`; a grasp far from it lets the
  object turn in the fingers, or closes on a cylinder's chord; lines more than
  ``max_centroid_offset_m`` from it are not offered), then narrowest; at most ``max_candidates``, two lines of one axis at least two steps apart.

The 2.5-D assumption: what is seen from above extends down to what is under it (occluded
space counts as material where the object's points are above it, as free elsewhere). The rule in
words: docs/method.md §3.2.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Optional

import numpy as np

from ... import _core
from ...robot.description import HandClearances
from ...robot.limits import GRIPPER_MAX_WIDTH_M
from ..config import GraspConfig, GraspFitConfig
from ..scene.scene_cloud import ENVIRONMENT, SceneCloud

#: Points farther than this beyond the object's footprint cannot touch the hand (the Franka
#: hand's half length, 0.1 m, plus its spheres' reach) — a search radius, not a tolerance.
_HAND_REACH_M = 0.15


@dataclass(frozen=True)
class FittedLine:
    """One closing line checked on the points. ``ok`` or ``reason``; ``position`` the contact
    point (world), ``closing`` (3,) the closing axis, ``width_m`` the material span,
    ``clearance_m`` of the finger columns, ``centroid_offset_m`` of the line's centre."""

    ok: bool
    reason: str
    axis: int
    offset_m: float
    position: Optional[np.ndarray] = None
    closing: Optional[np.ndarray] = None
    width_m: float = 0.0
    clearance_m: float = 0.0
    centroid_offset_m: float = 0.0

    def grasp(self, n: np.ndarray):
        """The ``_core.BestGrasp`` of this line (approach = -n, closing axis column 2)."""
        c = self.closing
        y = np.cross(c, n)
        R = np.column_stack([-n, y / np.linalg.norm(y), -c])
        return _core.BestGrasp(R, np.asarray(self.position, float), float(self.width_m))


@dataclass(frozen=True)
class _Frame:
    origin: np.ndarray  # (3,) world point on the table under the box centre
    e_c: np.ndarray     # (3,) horizontal closing axis
    e_a: np.ndarray     # (3,) horizontal axis across it
    n: np.ndarray


def _frames(track, cloud: SceneCloud) -> list[_Frame]:
    e = track.smoothed
    n = cloud.plane_n
    R = np.asarray(e.R_box, float)
    centre = np.asarray(e.center, float)
    origin = centre - (float(n @ centre) + cloud.plane_c) * n
    out = []
    for k in (0, 1):
        c = R[:, k] - float(R[:, k] @ n) * n
        c /= np.linalg.norm(c)
        out.append(_Frame(origin, c, np.cross(n, c), n))
    return out


def _local(frame: _Frame, pts: np.ndarray, cloud: SceneCloud) -> np.ndarray:
    d = pts - frame.origin
    return np.column_stack([d @ frame.e_c, d @ frame.e_a, cloud.heights_m(pts)])


def _rect_dist(c: np.ndarray, a: np.ndarray, c_lo: float, c_hi: float, half_a: float) -> np.ndarray:
    dc = np.maximum(np.maximum(c_lo - c, c - c_hi), 0.0)
    da = np.maximum(np.abs(a) - half_a, 0.0)
    return np.hypot(dc, da)


@dataclass(frozen=True)
class LineCheck:
    """Outcome of the point checks of one line: ``ok`` or ``reason``; the material's centre
    ``mid_c`` and ``width_m``; the finger columns' ``clearance_m``; the ``contact_h`` used."""

    ok: bool
    reason: str
    mid_c: float = 0.0
    width_m: float = 0.0
    clearance_m: float = 0.0
    contact_h: float = 0.0


@dataclass(frozen=True)
class LineLimits:
    """What a line must respect: the hand, the opening margin, the width range, the object's
    top height (the pads must overlap it by ``min_pad_overlap_m``), the point-check params."""

    hand: HandClearances
    open_margin_m: float
    min_width_m: float
    max_width_m: float
    top_h: float
    palm_clearance_m: float
    cfg: GraspFitConfig
    max_opening_m: float = GRIPPER_MAX_WIDTH_M  # the hand's largest opening (robot/limits.py)
    box_half_c: float = np.inf  # half the tracked box's extent along the closing axis

    def opening(self, width_m: float) -> float:
        """The fingers' gap while approaching: width + margin, at most the gripper's opening."""
        return min(width_m + self.open_margin_m, self.max_opening_m)


def _material(own: np.ndarray, a0: float, pad_bottom: float, lim: LineLimits):
    strip = own[(np.abs(own[:, 1] - a0) <= 0.5 * lim.hand.finger_width_m) & (own[:, 2] >= pad_bottom)]
    if len(strip) < lim.cfg.min_material_points:
        return None, f"no material between the pads ({len(strip)} points)"
    bound = lim.box_half_c + lim.cfg.column_tolerance_m  # the measured box bounds the object
    lo = max(float(strip[:, 0].min()), -bound)
    hi = min(float(strip[:, 0].max()), bound)
    if hi - lo > lim.max_width_m:
        return None, f"too wide to close on: {(hi - lo) * 1e3:.0f} mm"
    need = lim.cfg.min_contact_fraction * lim.hand.finger_width_m
    for side in (strip[strip[:, 0] >= hi - lim.cfg.contact_depth_m],
                 strip[strip[:, 0] <= lo + lim.cfg.contact_depth_m]):
        if float(np.ptp(side[:, 1])) < need:
            return None, "a pad would touch the material only at its edge"
    return (0.5 * (lo + hi), max(hi - lo, lim.min_width_m)), ""


def _fingers(near: np.ndarray, a0: float, mid: float, width: float, pad_bottom: float,
             lim: LineLimits) -> tuple[int, float]:
    """(points in the worse finger column, clearance [m]) of the two descent columns."""
    hand, cfg, tol = lim.hand, lim.cfg, lim.cfg.column_tolerance_m
    pts = near[near[:, 2] >= pad_bottom - tol]
    inner = 0.5 * lim.opening(width)
    worst, best = 0, np.inf
    for sign in (1.0, -1.0):
        c0 = mid + sign * inner
        c_lo, c_hi = (c0, c0 + hand.finger_thickness_m) if sign > 0 else (c0 - hand.finger_thickness_m, c0)
        d = _rect_dist(pts[:, 0], pts[:, 1] - a0, c_lo, c_hi, 0.5 * hand.finger_width_m)
        worst = max(worst, int(np.count_nonzero(d <= tol)))
        if len(d) > cfg.blocked_points:
            best = min(best, float(np.partition(d, cfg.blocked_points)[cfg.blocked_points]))
    return worst, best


@dataclass(frozen=True)
class HandSpheres:
    """The planner's spheres of the hand and fingers in the TCP frame (x across the closing
    axis, y along it, z the approach): ``centres_closed`` at a zero opening, ``per_opening``
    (S, 3) their shift per metre of opening (the fingers), ``radii`` (S,)."""

    centres_closed: np.ndarray
    per_opening: np.ndarray
    radii: np.ndarray

    def at(self, opening_m: float) -> np.ndarray:
        return self.centres_closed + opening_m * self.per_opening


def _sphere_need(boxes: np.ndarray, a0: float, mid: float, opening_m: float,
                 spheres: HandSpheres) -> float:
    """The lowest contact height at which no hand sphere, coming straight down, meets a box
    sample (``boxes``: local (c, a, h) samples of the neighbours' grown boxes, optionally a
    4th column: how much farther than the sphere's radius a sample must stay — environment
    points, kept at the planner's margin); both closing signs (the planner chooses one by
    the arm's posture)."""
    if len(boxes) == 0:
        return -np.inf
    cen, rad = spheres.at(opening_m), spheres.radii
    grow = boxes[:, 3] if boxes.shape[1] > 3 else np.zeros(len(boxes))
    need = -np.inf
    for s in (1.0, -1.0):
        dc = boxes[:, 0][None, :] - (mid + s * cen[:, 1])[:, None]
        da = boxes[:, 1][None, :] - (a0 + s * cen[:, 0])[:, None]
        d2 = (rad[:, None] + grow[None, :]) ** 2 - dc ** 2 - da ** 2
        hit = d2 > 0
        if np.any(hit):
            k, p = np.nonzero(hit)
            need = max(need, float(np.max(boxes[p, 2] + np.sqrt(d2[k, p]) + cen[k, 2])))
    return need


def check_line(own: np.ndarray, obstacles: np.ndarray, a0: float, contact_h: float,
               lim: LineLimits, boxes: np.ndarray = np.zeros((0, 3)),
               spheres: Optional[HandSpheres] = None) -> LineCheck:
    """The point checks of one line at ``a0`` (module doc). ``own`` / ``obstacles``: (N, 3)
    local (c, a, h) points of the object / of everything else that can block a finger;
    ``boxes``: samples of the neighbours' boxes as the planner models them, checked against
    the planner's hand ``spheres``. When a sphere would meet a box, the contact is raised once
    (as far as the pads still overlap the object's top by ``min_pad_overlap_m``)."""
    hand, cfg = lim.hand, lim.cfg
    for attempt in (0, 1):
        pad_bottom = contact_h - hand.pad_below_tcp_m
        mat, why = _material(own, a0, pad_bottom, lim)
        if mat is None:
            return LineCheck(False, why)
        mid, width = mat
        others = np.vstack([obstacles, own[np.abs(own[:, 1] - a0) > 0.5 * hand.finger_width_m
                                           + cfg.column_tolerance_m]])
        blocked, clear = _fingers(others, a0, mid, width, pad_bottom, lim)
        if blocked > cfg.blocked_points:
            return LineCheck(False, f"a finger blocked by {blocked} points", mid, width)
        opening = lim.opening(width)
        need = -np.inf if spheres is None else _sphere_need(boxes, a0, mid, opening, spheres)
        if need <= contact_h + 1e-4:
            return LineCheck(True, "", mid, width, clear, contact_h)
        limit = lim.top_h + hand.pad_below_tcp_m - cfg.min_pad_overlap_m
        if attempt or need > limit:
            return LineCheck(False, f"the hand meets a neighbour unless raised "
                                    f"{(need - contact_h) * 1e3:.0f} mm", mid, width)
        contact_h = need
    return LineCheck(False, "unreachable")


def surface_levels(own: np.ndarray, cell_m: float, gap_m: float, min_columns: int = 1) -> list[float]:
    """Heights of the lower steps of an object seen from above: the tops of the grid columns
    of its points (``own``: local (c, a, h)), sorted, each kept where at least ``min_columns``
    tops (itself included) lie within a quarter of ``gap_m`` of it (the few tops of columns on
    an upper box's sides, at any height between the levels, do not bridge a step); wherever
    two successive kept tops differ by more than ``gap_m`` the lower one is a step (a box on a
    box merged into one cluster, a bottle's shoulder). Highest step first."""
    ij = np.floor(own[:, :2] / cell_m).astype(np.int64)
    ij -= ij.min(axis=0)
    key = ij[:, 0] * (int(ij[:, 1].max()) + 1) + ij[:, 1]
    order = np.lexsort((own[:, 2], key))
    last = np.r_[key[order][1:] != key[order][:-1], True]
    tops = np.sort(own[order][last, 2])
    tops = tops[_shared(tops, 0.25 * gap_m, min_columns)]
    gaps = np.nonzero(np.diff(tops) > gap_m)[0]
    return [float(tops[g]) for g in gaps[::-1]]


def _shared(tops: np.ndarray, tol_m: float, n: int) -> np.ndarray:
    """Mask of the sorted ``tops`` with at least ``n`` tops (itself included) within ``tol_m``."""
    lo = np.searchsorted(tops, tops - tol_m, side="left")
    hi = np.searchsorted(tops, tops + tol_m, side="right")
    return hi - lo >= n


def contact_height_m(height_m: float, hand: HandClearances, config: GraspConfig) -> float:
    """Height [m] above the table plane of the contact point of a top-down grasp of an object
    ``height_m`` tall (ours): method.md §3's box centre (``height_m / 2``), raised where the hand
    needs it — the pads' lowest point stays ``table_clearance_m`` above the table (a 2 cm
    soap bar grasped at 1 cm put the pads on the table) and the palm stays
    ``palm_clearance_m`` above the object's top (a 20 cm bottle grasped at 10 cm put the palm
    on the bottle). Measured in clutter: these two were 4 of the first 12 failed attempts."""
    return max(0.5 * height_m, hand.pad_below_tcp_m + config.table_clearance_m,
               height_m + config.palm_clearance_m - hand.palm_above_tcp_m)


def _heights(track, own: np.ndarray, hand: HandClearances, grasp_cfg: GraspConfig,
             cfg: GraspFitConfig, band_m: float) -> list[float]:
    """Contact heights to try: method.md §3 / ours for the whole height; for an object whose lowest
    visible point is high (lying on something), centred between that point and its top; and
    just above each lower step of its top surface (the upper part alone: a box on a box seen
    as one cluster), where the pads still overlap the part above by ``min_pad_overlap_m`` —
    never so low that the palm meets the object's top (a mug's inside, a bottle's shoulder are
    steps too)."""
    height = float(track.smoothed.height_m)
    out = [contact_height_m(height, hand, grasp_cfg)]
    bottom = float(own[:, 2].min())
    if bottom > band_m + cfg.support_gap_m:
        out.append(contact_height_m(height - bottom, hand, grasp_cfg) + bottom)
    palm_over_top = height + grasp_cfg.palm_clearance_m - hand.palm_above_tcp_m
    for level in surface_levels(own, cfg.footprint_cell_m, cfg.level_gap_m, cfg.level_min_columns):
        ch = max(level + grasp_cfg.table_clearance_m + hand.pad_below_tcp_m, palm_over_top)
        if ch <= height + hand.pad_below_tcp_m - cfg.min_pad_overlap_m and ch not in out:
            out.append(ch)
    return out


def footprint_centroid(points: np.ndarray, cell_m: float) -> np.ndarray:
    """The centroid of the grid cells (x, y) the points occupy, at the points' mean height: the
    centre of the object's area seen from above. Unlike the points' mean it is not pulled
    towards the side the camera sees (an oblique view puts many points on the near wall)."""
    cells = np.unique(np.floor(points[:, :2] / cell_m).astype(np.int64), axis=0)
    return np.r_[(cells.mean(axis=0) + 0.5) * cell_m, points[:, 2].mean()]


def box_samples(boxes, plane_n: np.ndarray, plane_c: float, margin_m: float, step_m: float) -> np.ndarray:
    """(N, 4) points on the top faces of upright ``boxes`` (``OrientedBox``), their footprints
    grown by ``margin_m``, and each sample's slack [m]: the planner's model of the neighbours,
    as points (each column from the table up to the box top is blocked; the top face stands
    for it). Samples lie at most ``step_m`` apart with the face's edges included; a point of
    the face lies within the slack (half a sample cell's diagonal) of a sample, so a hand
    sphere kept that much farther from every sample stays clear of the face."""
    out = []
    for b in boxes:
        R, e, c = np.asarray(b.R, float), np.asarray(b.extents, float), np.asarray(b.center, float)
        hu, hv = 0.5 * e[0] + margin_m, 0.5 * e[1] + margin_m
        nu, nv = (int(np.ceil(2.0 * h / step_m)) + 1 for h in (hu, hv))
        U, V = np.meshgrid(np.linspace(-hu, hu, nu), np.linspace(-hv, hv, nv))
        slack = 0.5 * float(np.hypot(2.0 * hu / (nu - 1), 2.0 * hv / (nv - 1)))
        top = c + 0.5 * e[2] * R[:, 2]
        pts = top + np.outer(U.ravel(), R[:, 0]) + np.outer(V.ravel(), R[:, 1])
        out.append(np.c_[pts, np.full(len(pts), slack)])
    return np.vstack(out) if out else np.zeros((0, 4))


def _environment_obstacles(lc: SceneCloud, h_all: np.ndarray, box, cell_m: float,
                           cleared_m: float) -> np.ndarray:
    """Environment points above the table band and outside ``box`` (the target's estimate)
    grown by ``cleared_m`` (the planner ignores them in the final approach), as the centres of
    the ``cell_m`` grid cells (at the box centre) holding them — the planner's own rounding of
    the points near the target."""
    env = lc.points[(lc.owner == ENVIRONMENT) & (h_all > lc.band_m)]
    if len(env) == 0:
        return env
    R, c = np.asarray(box.R_box, float), np.asarray(box.center, float)
    half = 0.5 * np.asarray(box.extents, float) + cleared_m
    env = env[~np.all(np.abs((env - c) @ R) <= half, axis=1)]
    cells = np.unique(np.floor((env - c) / cell_m).astype(np.int64), axis=0)
    return c + (cells + 0.5) * cell_m


@dataclass(frozen=True)
class Neighbours:
    """The other objects as the planner models them: ``boxes`` (``OrientedBox``) and
    ``tops`` (M, 3) world column tops of those modelled by their points
    (:mod:`grasp_pipeline.motion.object_points`), kept ``tops_slack_m`` farther (the planner's
    margin plus the cells' rounding)."""

    boxes: tuple = ()
    tops: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    tops_slack_m: float = 0.0

    def near(self, xy, radius_m: float) -> "Neighbours":
        """The same, with only the tops within ``radius_m`` horizontally of ``xy``."""
        t = np.asarray(self.tops, float).reshape(-1, 3)
        keep = np.hypot(t[:, 0] - float(xy[0]), t[:, 1] - float(xy[1])) <= radius_m
        return replace(self, tops=t[keep])


def _planner_obstacles(lc: SceneCloud, h_all: np.ndarray, box, neighbours: Neighbours,
                       box_margin_m: float, cfg: GraspFitConfig,
                       env_grid: tuple[float, float, float]) -> np.ndarray:
    """(N, 4) world samples of what the planner keeps the hand spheres away from, each with
    its slack [m]: the neighbours' box top faces (kept ``box_margin_m`` farther, in 3-D — also
    above their tops), the column tops of the neighbours modelled by their points, and the
    environment points outside the target's ``box`` (``env_grid``: see :func:`fit_lines`)."""
    box_pts = box_samples(neighbours.boxes, lc.plane_n, lc.plane_c, 0.0, cfg.box_sample_step_m)
    box_pts[:, 3] += box_margin_m
    tops = np.c_[neighbours.tops, np.full(len(neighbours.tops), neighbours.tops_slack_m)]
    env_pts = _environment_obstacles(lc, h_all, box, env_grid[1], env_grid[2])
    return np.vstack([box_pts, tops, np.c_[env_pts, np.full(len(env_pts), env_grid[0])]])


def _reach_m(track) -> float:
    """How far horizontally from ``track``'s centre anything can touch the hand [m]."""
    return 0.5 * float(np.hypot(*np.asarray(track.smoothed.extents)[:2])) + _HAND_REACH_M


def _points_near(track, cloud: SceneCloud):
    """The scene's points within the hand's reach of ``track``: (cloud, mask of the track's own
    points, heights [m], points that can block a finger — other objects, untracked clusters,
    environment above the table band)."""
    lc = cloud.near(np.asarray(track.smoothed.center)[:2], _reach_m(track))
    own_mask = lc.owner == int(track.tid)
    h_all = lc.heights_m()
    return lc, own_mask, h_all, lc.points[~own_mask & ((lc.owner != ENVIRONMENT) | (h_all > lc.band_m))]


def _limits(track, hand: HandClearances, grasp_cfg: GraspConfig, cfg: GraspFitConfig,
            min_width_m: float, max_width_m: float) -> LineLimits:
    return LineLimits(hand, grasp_cfg.open_margin_m, min_width_m, max_width_m,
                      float(track.smoothed.height_m), grasp_cfg.palm_clearance_m, cfg)


def box_grasp_blocked(track, cloud: SceneCloud, grasp, hand: HandClearances, grasp_cfg: GraspConfig,
                      cfg: GraspFitConfig, max_width_m: float, neighbours: Optional[Neighbours] = None,
                      box_margin_m: float = 0.0, spheres: Optional[HandSpheres] = None,
                      env_grid: tuple[float, float, float] = (0.0, 0.005, 0.0)) -> str:
    """Why method.md §3's box ``grasp`` (``_core.BestGrasp``) of ``track`` cannot come down ('' when
    it can): the checks of the fitted lines (module doc) for the box grasp's closing line, pads
    centred on its contact point, opened to its width + margin. A finger column holding more
    than ``blocked_points`` points of anything but the object's material between the pads would
    push into a neighbour, the pile or the object itself; with the planner's hand ``spheres`` the
    hand must also stay clear of the neighbours' boxes and the environment points as the planner
    keeps them (``neighbours``, ``box_margin_m``, ``env_grid``: see :func:`fit_lines`) —
    the planner refuses such a grasp at the pre-grasp. Unlike a fitted line it is not raised."""
    lc, own_mask, h_all, obst_pts = _points_near(track, cloud)
    n = lc.plane_n
    c = np.asarray(grasp.R, float)[:, 2]
    c = c - float(c @ n) * n
    p = np.asarray(grasp.position, float)
    contact_h = float(lc.heights_m(p[None, :])[0])
    fr = _Frame(p - contact_h * n, c / np.linalg.norm(c), np.cross(n, c / np.linalg.norm(c)), n)
    lim = _limits(track, hand, grasp_cfg, cfg, 0.0, max_width_m)
    own = _local(fr, lc.points[own_mask], lc)
    others = np.vstack([_local(fr, obst_pts, lc),
                        own[np.abs(own[:, 1]) > 0.5 * hand.finger_width_m + cfg.column_tolerance_m]])
    blocked, _ = _fingers(others, 0.0, 0.0, float(grasp.width_m), contact_h - hand.pad_below_tcp_m, lim)
    if blocked > cfg.blocked_points:
        return f"a finger blocked by {blocked} points"
    if spheres is None:
        return ""
    near = (neighbours or Neighbours()).near(np.asarray(track.smoothed.center)[:2], _reach_m(track))
    obst = _planner_obstacles(lc, h_all, track.smoothed, near, box_margin_m, cfg, env_grid)
    boxes = np.c_[_local(fr, obst[:, :3], lc), obst[:, 3]]
    need = _sphere_need(boxes, 0.0, 0.0, lim.opening(float(grasp.width_m)), spheres)
    if need > contact_h + 1e-4:
        return f"the hand meets a neighbour unless raised {(need - contact_h) * 1e3:.0f} mm"
    return ""


def fit_lines(track, cloud: SceneCloud, hand: HandClearances, grasp_cfg: GraspConfig,
              cfg: GraspFitConfig, min_width_m: float, max_width_m: float,
              neighbours: Optional[Neighbours] = None, box_margin_m: float = 0.0,
              spheres: Optional[HandSpheres] = None,
              env_grid: tuple[float, float, float] = (0.0, 0.005, 0.0)) -> list[FittedLine]:
    """Every checked line of ``track`` (ok and not), in no particular order.
    ``neighbours``: the other objects as the planner models them (:class:`Neighbours`: box top
    faces sampled, kept ``box_margin_m`` clear of the planner's hand ``spheres``, and column tops
    of those modelled by their points), as the planner keeps them; so are the environment
    points above the table band outside the target's box (unsegmented parts of a pile, which
    the planner's occupancy map holds): ``env_grid`` = (margin [m], grid cell [m], cleared
    padding [m]), the planner's margin, its rounding of the points near the target and how
    far around the target's box it ignores them."""
    e = track.smoothed
    lc, own_mask, h_all, obst_pts = _points_near(track, cloud)
    if not np.any(own_mask):
        return []
    near = (neighbours or Neighbours()).near(np.asarray(e.center)[:2], _reach_m(track))
    box_pts = _planner_obstacles(lc, h_all, e, near, box_margin_m, cfg, env_grid)
    centroid = footprint_centroid(lc.points[own_mask], cfg.footprint_cell_m)
    lim = _limits(track, hand, grasp_cfg, cfg, min_width_m, max_width_m)
    out = []
    for k, fr in enumerate(_frames(track, lc)):
        lim = replace(lim, box_half_c=0.5 * float(np.asarray(e.extents)[k]))
        own = _local(fr, lc.points[own_mask], lc)
        obst = _local(fr, obst_pts, lc)
        boxes = np.c_[_local(fr, box_pts[:, :3], lc), box_pts[:, 3]]
        a_cent = float((centroid - fr.origin) @ fr.e_a)
        a_lo, a_hi = float(own[:, 1].min()), float(own[:, 1].max())
        offsets = sorted(set(np.round(np.arange(a_lo, a_hi + 1e-9, cfg.line_step_m), 4)) | {round(a_cent, 4)})
        for ch in _heights(track, own, hand, grasp_cfg, cfg, lc.band_m):
            for a0 in offsets:
                r = check_line(own, obst, a0, ch, lim, boxes, spheres)
                pos = fr.origin + r.mid_c * fr.e_c + a0 * fr.e_a + r.contact_h * fr.n
                off = abs(a0 - a_cent)
                out.append(FittedLine(r.ok, r.reason, k, float(a0), pos, fr.e_c, r.width_m,
                                      r.clearance_m, off))
    return out


def rank_lines(lines: list[FittedLine], cfg: GraspFitConfig) -> list[FittedLine]:
    """The free lines, best first (module doc), near-duplicates dropped."""
    free = sorted((ln for ln in lines if ln.ok and ln.centroid_offset_m <= cfg.max_centroid_offset_m),
                  key=lambda ln: (ln.clearance_m < cfg.clearance_enough_m,
                                  round(ln.centroid_offset_m / cfg.line_step_m), ln.width_m))
    chosen: list[FittedLine] = []
    for ln in free:
        if any(c.axis == ln.axis and abs(c.offset_m - ln.offset_m) < 2 * cfg.line_step_m for c in chosen):
            continue
        chosen.append(ln)
        if len(chosen) >= cfg.max_candidates:
            break
    return chosen
