"""Where grasps come from: the :class:`GraspSource` protocol and two implementations.

The grasp action executes whatever ``_core.BestGrasp`` poses a source proposes (position =
contact point, rotation column 0 = approach into the object, column 2 = closing axis,
``width_m``, ``score``), trying them in order until one can be planned. It never learns who
produced them, so a learned grasp detector replaces the geometric one by implementing
:meth:`GraspSource.propose` — nothing in motion or execution changes.

* :class:`GeometricGraspSource` — with the scene's points (``GraspRequest.cloud``): top-down
  grasps fitted to the points first (:mod:`.grasp_fit`: material between the pads, both
  fingers' descent free, the opening fits; ranked by clearance), ours. Then, as the last
  resort: SPEC 3's top-down grasp from the target's box (the grasp the selection publishes
  every frame), then closing across the other side when it fits; both at a contact height
  that fits the hand (:func:`contact_height_m`, ours), and offered only when their fingers'
  descent is free on the points (:func:`.grasp_fit.box_grasp_blocked`).
* :class:`FixedGraspSource` — a fixed list of poses (known grasps, a replay, a test).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Callable, Optional, Protocol, Sequence, runtime_checkable

import numpy as np

from .. import _core
from ..motion.occupancy import cell_rounding_m, cleared_cell_m, cleared_rounding_m
from ..motion.object_points import PointModel
from ..motion.perceived_scene import PerceivedScene
from ..perception.scene_volume import SceneVolume
from ..motion.robot_spheres import hand_spheres_in_tcp
from ..robot.description import GRIPPER_MAX_WIDTH_M, HandClearances, hand_clearances, load_robot_model
from .config import GraspConfig, GraspFitConfig
from .grasp_fit import HandSpheres, Neighbours, box_grasp_blocked, fit_lines, rank_lines
from .scene_cloud import SceneCloud
from .selection import perpendicular_grasp

log = logging.getLogger("grasp_pipeline.grasp")


@dataclass(frozen=True)
class GraspRequest:
    """What a source may use to propose grasps of one object.

    ``anchor_xy``: where the user (or the default target list) pointed [m, world];
    ``target``: the selected track (``_core.Track``) or None; ``published``: the best grasp
    the selection published for it (SPEC 5) or None; ``scene``: the perceived scene (points,
    boxes); ``max_width_m``: the widest object the gripper can close on with its margin;
    ``cloud``: the scene's labelled points (:class:`~.scene_cloud.SceneCloud`) or None;
    ``min_width_m``: the narrowest graspable width; ``reach(grasp, pre_grasp_distance_m)``:
    the grasp with the hand orientation the arm reaches, or None when it reaches neither
    (:class:`~.grasping.reach.ArmReach`; None: not checked); ``volume``: the scene volume
    (:class:`~grasp_pipeline.perception.scene_volume.SceneVolume`: which places were seen
    free, occupied, or never seen) or None; ``unknown(points)``: True for the points (N, 3)
    no camera has seen free (from the volume; None: not known)."""

    anchor_xy: tuple[float, float]
    target: Optional[object]
    published: Optional[object]
    scene: PerceivedScene
    max_width_m: float
    cloud: Optional[SceneCloud] = None
    min_width_m: float = 0.005
    reach: Optional[Callable] = None
    volume: Optional[SceneVolume] = None
    unknown: Optional[Callable] = None


@runtime_checkable
class GraspSource(Protocol):
    """Proposes grasps for one object, best first (an empty list: no grasp).

    ``name`` names the source in reports. A source may also say ``top_down_only = True``
    (it proposes only top-down grasps: the selection then keeps SPEC 2.6's width guard) and
    keep ``last_refusal``, a sentence on why its last call proposed nothing."""

    name: str

    def propose(self, request: GraspRequest) -> list:
        """Grasp candidates (:class:`~.grasping.grasp.Grasp`, or anything with ``R``,
        ``position`` and ``width_m``), best first."""


def planner_hand_spheres(cell_m: float) -> HandSpheres:
    """The motion planner's hand and finger spheres (cell ``cell_m``) in the TCP frame, with
    the fingers' shift per metre of opening."""
    model = load_robot_model()
    c0, r = hand_spheres_in_tcp(model, cell_m, 0.0)
    c1, _ = hand_spheres_in_tcp(model, cell_m, GRIPPER_MAX_WIDTH_M)
    return HandSpheres(c0, (c1 - c0) / GRIPPER_MAX_WIDTH_M, r)


def contact_height_m(height_m: float, hand: HandClearances, config: GraspConfig) -> float:
    """Height [m] above the table plane of the contact point of a top-down grasp of an object
    ``height_m`` tall (ours): SPEC 3's box centre (``height_m / 2``), raised where the hand
    needs it — the pads' lowest point stays ``table_clearance_m`` above the table (a 2 cm
    soap bar grasped at 1 cm put the pads on the table) and the palm stays
    ``palm_clearance_m`` above the object's top (a 20 cm bottle grasped at 10 cm put the palm
    on the bottle). Measured in clutter: these two were 4 of the first 12 failed attempts."""
    return max(0.5 * height_m, hand.pad_below_tcp_m + config.table_clearance_m,
               height_m + config.palm_clearance_m - hand.palm_above_tcp_m)


def at_contact_height(grasp, plane, height_m: float, hand: HandClearances, config: GraspConfig):
    """``grasp`` moved along the plane normal to :func:`contact_height_m`."""
    n = np.asarray(plane.n, dtype=float)
    p = np.asarray(grasp.position, dtype=float)
    dz = contact_height_m(height_m, hand, config) - (float(n @ p) + float(plane.c))
    if abs(dz) < 1e-9:
        return grasp
    return _core.BestGrasp(np.asarray(grasp.R, dtype=float), p + dz * n, float(grasp.width_m))


class GeometricGraspSource:
    """Grasps fitted to the points when the request has them (:mod:`.grasp_fit`), then the
    published SPEC 3 grasp and the perpendicular one when that side fits, each at a contact
    height that fits the hand (:func:`contact_height_m`).

    ``config``: the grasp parameters (clearances); ``fit``: the point checks' parameters;
    ``hand``: the hand's extent around the TCP (default: read from the robot model);
    ``motion``: the planner's collision model (``MotionConfig``: sphere cell, margin) — with
    it a fitted grasp also clears the neighbours as the planner models them (boxes, or points
    where seen; hand spheres); None: only the points are checked."""

    name = "geometric"
    #: proposes top-down grasps only: the selection keeps SPEC 2.6's width guard
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
        """Fitted grasps first, then SPEC 3's box grasps whose fingers' descent is free on the
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
        """SPEC 3's box grasp and the perpendicular one, at :func:`contact_height_m`."""
        out = [] if request.published is None else [request.published]
        plane = request.scene.plane
        if request.target is not None and plane is not None:
            alt = perpendicular_grasp(request.target, plane, request.max_width_m)
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


class FixedGraspSource:
    """Grasps given up front; proposes those within ``radius_m`` of the anchor, nearest first."""

    name = "fixed"
    top_down_only = False

    def __init__(self, grasps: Sequence, radius_m: float = 0.05) -> None:
        self.grasps = list(grasps)
        if radius_m <= 0:
            raise ValueError(f"FixedGraspSource radius_m must be > 0, got {radius_m}")
        self.radius_m = float(radius_m)

    @classmethod
    def from_poses(cls, poses: Sequence[tuple[np.ndarray, np.ndarray, float]],
                   radius_m: float = 0.05) -> "FixedGraspSource":
        """From (R 3x3, position (3,), width_m) triples in the BestGrasp convention."""
        return cls([_core.BestGrasp(np.asarray(R, float), np.asarray(p, float), float(w))
                    for R, p, w in poses], radius_m)

    def propose(self, request: GraspRequest) -> list:
        ax, ay = request.anchor_xy
        near = [(float(np.hypot(g.position[0] - ax, g.position[1] - ay)), k, g)
                for k, g in enumerate(self.grasps)]
        return [g for d, _, g in sorted(near) if d <= self.radius_m]
