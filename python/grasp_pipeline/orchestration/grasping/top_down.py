"""The top-down grasp source (``grasp.grasp_source: top_down``): :class:`GeometricGraspSource`.

With the scene's points (``GraspRequest.cloud``): top-down grasps fitted to the points first
(:mod:`.fit`: material between the pads, both fingers' descent free, the opening fits; ranked
by clearance), ours. Then, as the last resort: method.md §3's top-down grasp from the target's box
(the grasp the selection publishes every frame), then closing across the other side when it
fits; both at a contact height that fits the hand (:func:`~.fit.contact_height_m`, ours), and
offered only when their fingers' descent is free on the points
(:func:`~.fit.box_grasp_blocked`).
"""

from __future__ import annotations

import logging
from typing import Optional

import numpy as np

from ... import _core
from ...motion.object_points import PointModel
from ...motion.occupancy import cell_rounding_m, cleared_cell_m, cleared_rounding_m
from ...motion.robot_spheres import hand_spheres_in_tcp
from ...robot.description import GRIPPER_MAX_WIDTH_M, HandClearances, hand_clearances, load_robot_model
from ..config import GraspConfig, GraspFitConfig
from ..scene.selection import perpendicular_grasp
from .fit import HandSpheres, Neighbours, box_grasp_blocked, contact_height_m, fit_lines, rank_lines
from .opening import full_margin_width_m
from .source import GraspRequest

log = logging.getLogger("grasp_pipeline.grasp")


def planner_hand_spheres(cell_m: float) -> HandSpheres:
    """The motion planner's hand and finger spheres (cell ``cell_m``) in the TCP frame, with
    the fingers' shift per metre of opening."""
    model = load_robot_model()
    c0, r = hand_spheres_in_tcp(model, cell_m, 0.0)
    c1, _ = hand_spheres_in_tcp(model, cell_m, GRIPPER_MAX_WIDTH_M)
    return HandSpheres(c0, (c1 - c0) / GRIPPER_MAX_WIDTH_M, r)


def at_contact_height(grasp, plane, height_m: float, hand: HandClearances, config: GraspConfig):
    """``grasp`` moved along the plane normal to :func:`~.fit.contact_height_m`."""
    n = np.asarray(plane.n, dtype=float)
    p = np.asarray(grasp.position, dtype=float)
    dz = contact_height_m(height_m, hand, config) - (float(n @ p) + float(plane.c))
    if abs(dz) < 1e-9:
        return grasp
    return _core.BestGrasp(np.asarray(grasp.R, dtype=float), p + dz * n, float(grasp.width_m))


class GeometricGraspSource:
    """Grasps fitted to the points when the request has them (:mod:`.fit`), then the
    published method.md §3 grasp and the perpendicular one when that side fits, each at a contact
    height that fits the hand (:func:`~.fit.contact_height_m`).

    ``config``: the grasp parameters (clearances); ``fit``: the point checks' parameters;
    ``hand``: the hand's extent around the TCP (default: read from the robot model);
    ``motion``: the planner's collision model (``MotionConfig``: sphere cell, margin) — with
    it a fitted grasp also clears the neighbours as the planner models them (boxes, or points
    where seen; hand spheres); None: only the points are checked."""

    name = "geometric"
    #: proposes top-down grasps only: the selection keeps method.md §2.6's width guard
    top_down_only = True

    def __init__(self, config: Optional[GraspConfig] = None, hand: Optional[HandClearances] = None,
                 fit: Optional[GraspFitConfig] = None, motion=None):
        self.config = config or GraspConfig()
        self.hand = hand or hand_clearances()
        self.fit = fit or GraspFitConfig()
        self.box_margin_m = 0.0 if motion is None else float(motion.collision_margin_m)
        self.spheres = None if motion is None else planner_hand_spheres(motion.sphere_cell_m)
        # neighbours seen well enough are the planner's point obstacles
        self.points_model = None if motion is None else PointModel.from_motion(motion)
        self._last_neighbours: Optional[tuple] = None  # (request, its Neighbours)
        #: why the last :meth:`propose` returned no grasp ("" when it returned some)
        self.last_refusal = ""
        self._fit_note, self._box_notes = "", []
        # environment points as the planner holds them near the target: on its fine grid,
        # kept at its margin plus that grid's rounding (OccupancyMap.with_cleared_region)
        self.env_grid = (0.0, 0.005, 0.0) if motion is None else (
            self.box_margin_m + cleared_rounding_m(float(motion.voxel_size_m)),
            cleared_cell_m(float(motion.voxel_size_m)), float(motion.target_ignore_padding_m))

    def _neighbours(self, request: GraspRequest) -> Neighbours:
        """The other objects as the planner will model them (boxes, or points where seen);
        computed once per request (the fitted lines and the box grasps share it)."""
        if self._last_neighbours is not None and self._last_neighbours[0] is request:
            return self._last_neighbours[1]
        nb = self._model_neighbours(request)
        self._last_neighbours = (request, nb)
        return nb

    def _model_neighbours(self, request: GraspRequest) -> Neighbours:
        tid = int(request.target.tid)
        scene = request.scene.without_fragments(tid, self.config.fragment_margin_m)
        if self.points_model is None:
            return Neighbours(tuple(b for b, t in zip(scene.boxes, scene.tids) if t != tid))
        boxes, tops = scene.obstacles(tid, self.points_model)
        return Neighbours(tuple(boxes), tops, self.box_margin_m + cell_rounding_m(self.points_model.cell_m))

    def propose(self, request: GraspRequest) -> list:
        """Fitted grasps first, then method.md §3's box grasps whose fingers' descent is free on the
        points (planning tries them in order: the box grasps are the last resort when no
        fitted one can be planned); none: :attr:`last_refusal` says why."""
        fitted, boxes = self.fitted(request), self.from_box(request)
        self.last_refusal = "" if fitted or boxes else (
            f"no closing line passes the point checks ({self._fit_note or 'no points of it'}); "
            f"box grasps: {'; '.join(self._box_notes) or 'none'}")
        return fitted + boxes

    def fitted(self, request: GraspRequest) -> list:
        """Grasps fitted to the points, best first ([] without points or when none passes)."""
        self._fit_note = ""
        if request.cloud is None or request.target is None or len(request.cloud) == 0:
            return []
        lines = fit_lines(request.target, request.cloud, self.hand, self.config, self.fit,
                          request.min_width_m, request.max_width_m,
                          self._neighbours(request), self.box_margin_m, self.spheres,
                          self.env_grid)
        ranked = rank_lines(lines, self.fit)
        if not ranked:
            reasons = sorted({ln.reason.split(" (")[0].split(" by ")[0].split(" unless")[0] if ln.reason else
                              "too far from the centroid" for ln in lines})
            self._fit_note = "; ".join(sorted({r.split(":")[0] for r in reasons}))
            log.info("no closing line of #%d passes the point checks (%d tried: %s); box grasps",
                     request.target.tid, len(lines), "; ".join(reasons) or "no points of it")
            return []
        best = ranked[0]
        log.info("#%d: %d of %d closing lines pass the point checks; best: axis %d, %.0f mm off the "
                 "centroid, width %.1f mm, clearance %.1f mm", request.target.tid,
                 sum(ln.ok for ln in lines), len(lines), best.axis, best.centroid_offset_m * 1e3,
                 best.width_m * 1e3, min(best.clearance_m, 1.0) * 1e3)
        n = request.cloud.plane_n
        return [ln.grasp(n) for ln in ranked]

    def from_box(self, request: GraspRequest) -> list:
        """method.md §3's box grasp and the perpendicular one, at :func:`~.fit.contact_height_m`."""
        out = [] if request.published is None else [request.published]
        plane = request.scene.plane
        if request.target is not None and plane is not None:
            # the box heuristic models the fingers at the whole open_margin_m around the box
            alt = perpendicular_grasp(request.target, plane, full_margin_width_m(self.config))
            if alt is not None:
                out.append(alt)
            height = float(request.target.smoothed.height_m)
            out = [at_contact_height(g, plane, height, self.hand, self.config) for g in out]
        return self._free(request, out)

    def _free(self, request: GraspRequest, grasps: list) -> list:
        """The box grasps whose fingers can come down on the scene's points and whose hand
        clears the neighbours as the planner models them (all of them without points): a box
        grasp pushing a finger into a neighbour, or one the planner would refuse at the
        pre-grasp, is not offered — the round picks another object first, as it does when no
        fitted grasp exists."""
        self._box_notes = []
        if request.cloud is None or request.target is None or len(request.cloud) == 0:
            return grasps
        neighbours = self._neighbours(request)
        out = []
        for g in grasps:
            why = box_grasp_blocked(request.target, request.cloud, g, self.hand, self.config,
                                    self.fit, request.max_width_m, neighbours, self.box_margin_m,
                                    self.spheres, self.env_grid)
            if why:
                log.info("box grasp of #%d not offered: %s", request.target.tid, why)
                self._box_notes.append(why)
            else:
                out.append(g)
        return out
