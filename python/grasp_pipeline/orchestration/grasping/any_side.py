"""The any-side (6-DoF) grasp source: grasps sampled on the perceived points, from any
direction within a tilt limit of the table normal.

:class:`AnySideGraspSource` proposes, for one object:

1. its solid model (:mod:`.target_model`: seen points with normals, hidden columns filled);
2. candidate frames (:mod:`.candidates`): approaches straight down and on tilted rings, closing
   axes about each (evenly spaced, and along seen surface normals: antipodal pairs), lines
   across the object;
3. the pads' contact checks on the object (:mod:`.contacts`): depth, material between the
   pads, width within the opening, contact patches, the fingers' way in;
4. the best ``preselect`` of those against the scene (:mod:`.clearance`; the next
   ``preselect`` while none passes, up to ``preselect_batches`` batches): the planner's hand
   spheres along the approach clear of the neighbours, the environment and the table; the
   palm and camera clear of the object; the fingers' sweep through space no camera has seen
   (when the request can tell, :class:`~grasp_pipeline.orchestration.grasping.source.GraspRequest`
   ``unknown``);
5. a score (:mod:`.scoring`), near-duplicates dropped, and the reach of the whole arm (the
   request's ``reach``: IK of the grasp and pre-grasp poses) for the best: reachable grasps
   first, each with the hand orientation the arm reaches.

When nothing passes, :attr:`AnySideGraspSource.last_refusal` says why (the most common
reasons among the candidates).
"""

from __future__ import annotations

import logging
import time
from collections import Counter
from typing import Optional

import numpy as np

from ...motion.object_points import PointModel, columns
from ...motion.occupancy import cell_rounding_m, cleared_cell_m
from ..config import GraspConfig, GraspFitConfig
from ..scene.scene_cloud import ENVIRONMENT
from .candidates import (approach_directions, approaches_across, build_frames, closing_axes,
                         concat_frames, dominant_normals, normal_axes, plane_basis)
from .clearance import ObstacleSet, hand_slack, palm_touches_target
from .config import SamplerConfig
from .contacts import OK, REASONS, ContactLimits, concat_contacts, evaluate
from .grasp import TOP_DOWN_TOLERANCE_DEG, Grasp
from .hand_model import HandModel, hand_model
from .scoring import dedupe, score
from .target_model import target_model

log = logging.getLogger("grasp_pipeline.grasp")

#: How far around the target the scene can touch the hand [m] (its half length plus reach).
_REACH_M = 0.18


class AnySideGraspSource:
    """Grasps from any side within ``config.max_tilt_deg`` of the table normal (module doc).

    ``grasp``: the grasp action's parameters (opening margin, clearances); ``fit``: the point
    checks' parameters shared with the top-down fit; ``motion``: the planner's collision model
    (margins, cells) — the sampler keeps the planner's clearances so that what it proposes can
    be planned."""

    name = "any_side"
    top_down_only = False

    def __init__(self, config: Optional[SamplerConfig] = None, grasp: Optional[GraspConfig] = None,
                 fit: Optional[GraspFitConfig] = None, motion=None,
                 hand: Optional[HandModel] = None) -> None:
        self.config = config or SamplerConfig()
        self.grasp_config = grasp or GraspConfig()
        self.fit = fit or GraspFitConfig()
        self.motion = motion
        self.hand = hand or hand_model(0.04 if motion is None else float(motion.sphere_cell_m))
        self.margin_m = 0.005 if motion is None else float(motion.collision_margin_m)
        self.cleared_pad_m = 0.05 if motion is None else float(motion.target_ignore_padding_m)
        voxel = 0.01 if motion is None else float(motion.voxel_size_m)
        self.cell_m = cleared_cell_m(voxel)
        self.points_model = None if motion is None else PointModel.from_motion(motion)
        self.last_refusal = ""
        self.last_timing_ms = 0.0
        #: CPU time [ms] of every proposal so far (the reach check included)
        self.cpu_ms: list[float] = []

    # ------------------------------------------------------------------ public
    def propose(self, request) -> list:
        """:class:`~.grasp.Grasp` candidates of ``request.target``, best first."""
        c0 = time.thread_time()
        try:
            grasps = self._propose(request)
        finally:
            self.last_timing_ms = (time.thread_time() - c0) * 1e3
            self.cpu_ms.append(self.last_timing_ms)
        if not grasps:
            tid = getattr(request.target, "tid", None)
            log.info("#%s: no any-side grasp: %s", tid, self.last_refusal)
        return grasps

    def _propose(self, request) -> list:
        self.last_refusal = ""
        cloud, track = request.cloud, request.target
        if cloud is None or track is None or len(cloud) == 0:
            self.last_refusal = "no points of the object in the latest frame"
            return []
        viewpoint = self._viewpoint(request)
        target = target_model(cloud, int(track.tid), viewpoint, self.config.cell_m, self.config.max_points,
                              unknown=getattr(request, "unknown", None), max_cell_m=self.config.max_cell_m)
        if target is None:
            self.last_refusal = f"no points of #{track.tid} in the latest frame"
            return []
        frames = self._frames(target, cloud.plane_n, track.smoothed.R_box)
        lim = self._limits(request)
        con = evaluate(frames, target, self.hand, lim, cloud.plane_n, cloud.plane_c)
        frames, con = self._above_steps(target, frames, con, lim, cloud)
        ok = np.nonzero(con.code == OK)[0]
        if len(ok) == 0:
            self.last_refusal = self._summary(con.code, len(frames))
            return []
        pre = score(con, frames, self.config, lim, None, None)
        return self._finish_in_batches(request, target, frames, con, ok[np.argsort(-pre[ok], kind="stable")], lim)

    def _finish_in_batches(self, request, target, frames, con, ranked, lim) -> list:
        """The scene checks and the reach (:meth:`_finish`) of the ``preselect`` best frames of
        ``ranked``, then of the next ``preselect`` while none of a batch passes, up to
        ``preselect_batches`` batches: when a neighbour blocks the side the best-scored frames
        all come in from, the grasps from another side rank lower. The refusal is the first
        batch's, with how many more were checked."""
        n = self.config.preselect
        batches = [ranked[k:k + n] for k in range(0, min(len(ranked), n * self.config.preselect_batches), n)]
        obs = self._obstacles(request)
        first = ""
        for batch in batches:
            grasps = self._finish(request, target, frames, con, batch, lim, obs)
            if grasps:
                return grasps
            first = first or self.last_refusal
        more = sum(len(b) for b in batches[1:])
        self.last_refusal = first + (f" (and none of the next {more} candidates)" if more else "")
        return []

    # ------------------------------------------------------------------ steps
    def _viewpoint(self, request) -> np.ndarray:
        T = getattr(request.scene, "T_world_camera", None)
        if T is not None:
            return np.asarray(T, float)[:3, 3]
        c = np.asarray(request.target.smoothed.center, float)
        return c + np.array([0.0, 0.0, 0.4])

    def _frames(self, target, plane_n, box_R=None):
        """The candidate frames; ``box_R``: the tracked box's axes, whose horizontal ones are
        closing axes too (across a box's faces, not at the grid's nearest angle)."""
        cfg = self.config
        tilts = [t for t in cfg.tilts_deg if t <= cfg.max_tilt_deg]
        dirs, tilt = approach_directions(plane_n, tilts, cfg.azimuths, away_from=np.zeros(3))
        normals = target.normals[target.seen]
        if cfg.normal_axes and len(normals):
            rng = np.random.default_rng(0)
            normals = normals[rng.choice(len(normals), min(cfg.normal_axes, len(normals)), replace=False)]
        box_axes = np.zeros((0, 3)) if box_R is None else np.asarray(box_R, float)[:, :2].T
        axes = []
        for a in dirs:
            extra = [normal_axes(a, box_axes)] if len(box_axes) else []
            if cfg.normal_axes and len(normals):
                extra.append(normal_axes(a, normals))
            axes.append(np.vstack([closing_axes(a, cfg.rotations), *extra]))
        faces = dominant_normals(target.normals[target.seen], cfg.normal_axes)
        a2, t2, c2 = approaches_across(faces, plane_n, cfg.max_tilt_deg)
        dirs = np.vstack([dirs, a2])
        tilt = np.r_[tilt, t2]
        axes += [c[None, :] for c in c2]
        return build_frames(target.points, target.centroid, dirs, tilt, axes, cfg.line_spacing_m, cfg.lines)

    def _above_steps(self, target, frames, con, lim, cloud):
        """The top-down frames once more, held just above each lower step of the object's top
        surface (:func:`~.fit.surface_levels`): the upper box of a stack that
        segmentation merged into one cluster is grasped alone, not across the box under it.
        Returns all frames and their contacts."""
        from .fit import surface_levels

        n, c0 = np.asarray(cloud.plane_n, float), float(cloud.plane_c)
        top_down = np.nonzero(frames.tilt_deg <= TOP_DOWN_TOLERANCE_DEG)[0]
        if len(top_down) == 0:
            return frames, con
        h = target.points @ n + c0
        u, v = plane_basis(n)
        levels = surface_levels(np.column_stack([target.points @ u, target.points @ v, h]),
                                self.fit.footprint_cell_m, self.fit.level_gap_m, self.fit.level_min_columns)
        sub = frames.take(top_down)
        for level in levels[: self.config.step_levels]:
            # straight down, depth along the approach = c0 - height: the pads' lowest point
            # stays table_clearance_m above the step
            cap = c0 - level - self.grasp_config.table_clearance_m - self.hand.pad_half_length_m
            extra = evaluate(sub, target, self.hand, lim, n, c0, depth_cap=np.full(len(sub), cap))
            frames, con = concat_frames(frames, sub), concat_contacts(con, extra)
        return frames, con

    def _limits(self, request) -> ContactLimits:
        g, f = self.grasp_config, self.fit
        opening = self.hand.max_opening_m
        return ContactLimits(max_width_m=request.max_width_m,
                             min_width_m=request.min_width_m, open_margin_m=g.open_margin_m,
                             max_opening_m=opening, palm_clearance_m=g.palm_clearance_m,
                             table_clearance_m=g.table_clearance_m,
                             min_material_points=f.min_material_points, contact_depth_m=f.contact_depth_m,
                             min_contact_fraction=f.min_contact_fraction, blocked_points=f.blocked_points,
                             tolerance_m=f.column_tolerance_m, min_pad_overlap_m=f.min_pad_overlap_m,
                             friction_cone_deg=self.config.friction_cone_deg,
                             min_facing_fraction=self.config.min_facing_fraction)

    def _obstacles(self, request) -> ObstacleSet:
        cloud, track, scene = request.cloud, request.target, request.scene
        tid = int(track.tid)
        centre = np.asarray(track.smoothed.center, float)
        near = cloud.near(centre[:2], _REACH_M + 0.5 * float(np.hypot(*track.smoothed.extents[:2])))
        h = near.heights_m()
        others = (near.owner != tid) & ((near.owner != ENVIRONMENT) | (h > near.band_m))
        boxes, tops = (), np.zeros((0, 3))
        if self.points_model is not None:
            bx, tops = scene.without_fragments(tid, self.grasp_config.fragment_margin_m).obstacles(
                tid, self.points_model)
            boxes = tuple(bx)
        fixed = columns(tops, cloud.plane_n, cloud.plane_c, self.cell_m) if len(tops) else tops
        from ..scene.tracks import track_box

        return ObstacleSet(fixed=fixed, fixed_slack_m=self.margin_m + cell_rounding_m(self.cell_m),
                           clearable=near.points[others],
                           clearable_slack_m=self.margin_m + cell_rounding_m(self.cell_m),
                           boxes=boxes, box_slack_m=self.margin_m, plane_n=cloud.plane_n,
                           plane_c=cloud.plane_c,
                           cleared=track_box(track).inflated(self.cleared_pad_m), margin_m=self.margin_m)

    def _raise(self, request, target, frames, con, idx, lim, obs, backs):
        """Slack of the hand over the approach for the frames ``idx``; a frame whose hand meets
        a neighbour at the grasp is backed off along the approach by the deficit (up to
        ``max_raise_m`` in all, a few times: a sphere moving away from a column's corner gains
        less than it moves), as long as the pads still overlap the object.
        Returns (contacts of the frames, slack (K, 2))."""
        sub = frames.take(idx)
        merged = _subset(con, idx)
        slack = hand_slack(obs, self.hand, merged.tcp_positions(sub), sub.a, sub.c, merged.opening_m, backs)
        depth0 = merged.z_tcp.copy()
        for _ in range(3):
            best = slack.max(axis=1)
            short = np.nonzero((best < 0) & (depth0 - merged.z_tcp - best < self.config.max_raise_m)
                               & (merged.code == OK))[0]
            if len(short) == 0:
                break
            sub2 = sub.take(short)
            con2 = evaluate(sub2, target, self.hand, lim, request.cloud.plane_n, request.cloud.plane_c,
                            depth_cap=merged.z_tcp[short] + best[short] - 1e-3)
            slack2 = hand_slack(obs, self.hand, con2.tcp_positions(sub2), sub2.a, sub2.c,
                                con2.opening_m, backs)
            for j, i in enumerate(short):
                _assign(merged, int(i), con2, j)
                slack[i] = slack2[j]
        return merged, slack

    def _finish(self, request, target, frames, con, idx, lim, obs: ObstacleSet) -> list:
        cfg = self.config
        backs = tuple(cfg.approach_checks_m) + (self.grasp_config.pre_grasp_distance_m,)
        con, slack = self._raise(request, target, frames, con, idx, lim, obs, backs)
        sub, origins = frames.take(idx), con.tcp_positions(frames.take(idx))
        opening = con.opening_m
        idx_local = np.arange(len(idx))
        palm = palm_touches_target(self.hand, target.points, origins, sub.a, sub.c, opening,
                                   lim.tolerance_m)
        free = (slack >= 0.0) & ~palm  # (K, 2) per hand orientation
        unknown = self._unknown(request, sub, origins, con.y_mid, con.z_tcp, opening)
        usable = free.any(axis=1) & (unknown < cfg.unknown_max_fraction)
        if not np.any(usable):
            self.last_refusal = self._scene_summary(free, palm, unknown, len(idx))
            return []
        keep = np.nonzero(usable)[0]
        clearance = np.where(free, slack, -np.inf).max(axis=1)
        s = score(con, sub, cfg, lim, clearance, unknown, idx_local)
        order = keep[np.argsort(-s[keep], kind="stable")]
        order = dedupe(order, origins, sub.a, sub.c, cfg.duplicate_distance_m, cfg.duplicate_angle_deg)
        grasps = [self._grasp(request, sub, origins, con, k, s[k], free[k]) for k in order]
        grasps = self._reach_sorted(request, grasps)[: cfg.max_proposals]
        if grasps:
            log.info("#%d: %d any-side grasps (best: tilt %.0f deg, width %.1f mm, score %.2f) of "
                     "%d frames", request.target.tid, len(grasps), grasps[0].tilt_deg,
                     grasps[0].width_m * 1e3, grasps[0].score, len(frames))
        return grasps

    def _unknown(self, request, sub, origins, y_mid, z_tcp, opening) -> np.ndarray:
        """(K,) the larger share, of the two finger pads' places at the opening, that no camera
        has seen free (0 when the request cannot tell): a finger that would come down into
        unseen space may meet what nobody saw (under a leaning box, say)."""
        probe = getattr(request, "unknown", None)
        if probe is None or len(origins) == 0:
            return np.zeros(len(origins))
        offs = np.array([[x, 0.0, z] for x in (-0.006, 0.006) for z in (-0.008, 0.0, 0.008)])
        sides = []
        for side in (1.0, -1.0):
            y = side * (0.5 * opening[:, None] + 0.005)  # (K, 1)
            pts = (origins[:, None, :] + offs[None, :, :1] * sub.b[:, None, :]
                   + y[:, :, None] * sub.c[:, None, :] + offs[None, :, 2:3] * sub.a[:, None, :])
            sides.append(np.asarray(probe(pts.reshape(-1, 3)), float).reshape(len(origins), -1).mean(axis=1))
        return np.maximum(*sides)

    def _grasp(self, request, sub, origins, con, k, s, free_k) -> Grasp:
        a, c = sub.a[k], sub.c[k]
        if free_k[0]:
            tcp = np.column_stack([np.cross(c, a), c, a])
        else:
            tcp = np.column_stack([-np.cross(c, a), -c, a])
        return Grasp.from_axes(a, c, origins[k], float(con.width_m[k]), score=float(s),
                               source=self.name, target_tid=int(request.target.tid),
                               tilt_deg=float(sub.tilt_deg[k]),
                               tcp_R=tcp if free_k.sum() == 1 else None)

    def _reach_sorted(self, request, grasps: list) -> list:
        reach = getattr(request, "reach", None)
        if reach is None:
            return grasps
        reached = []
        for g in grasps[: self.config.reach_candidates]:
            r = reach(g, self.grasp_config.pre_grasp_distance_m)
            if r is not None:
                reached.append(r)
                if len(reached) >= self.config.max_proposals:
                    break
        if not reached:
            self.last_refusal = (f"none of the {min(len(grasps), self.config.reach_candidates)} best "
                                 "grasps is within the arm's reach")
        return reached

    # ------------------------------------------------------------------ reasons
    @staticmethod
    def _summary(codes: np.ndarray, total: int) -> str:
        counts = Counter(REASONS[int(c)] for c in codes if c != OK)
        top = ", ".join(f"{r} ({n})" for r, n in counts.most_common(3))
        return f"no grasp passes the contact checks ({total} frames: {top})"

    @staticmethod
    def _scene_summary(free, palm, unknown, total: int) -> str:
        parts = [f"the hand meets a neighbour, the table or the environment ({int((~free.any(axis=1)).sum())})",
                 f"the palm or camera meets the object ({int(palm.all(axis=1).sum())})"]
        if np.any(unknown > 0):
            parts.append(f"the fingers sweep unseen space ({int((unknown > 0.5).sum())})")
        return f"no grasp passes the scene checks ({total} candidates: " + "; ".join(parts) + ")"


def _subset(con, idx):
    """The contacts of the frames ``idx`` (a new :class:`~.contacts.Contacts`)."""
    from dataclasses import fields

    return type(con)(**{f.name: np.array(getattr(con, f.name)[idx]) for f in fields(con)})


def _assign(dst, i: int, src, j: int) -> None:
    """Row ``j`` of ``src`` into row ``i`` of ``dst`` (contacts of the same kind)."""
    from dataclasses import fields

    for f in fields(dst):
        getattr(dst, f.name)[i] = getattr(src, f.name)[j]
