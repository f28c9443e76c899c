"""Whether the released object arrived: the camera looks down into the tray, and the robot's
verdict "placed" needs the object seen there.

After the release the hand goes up and the camera (on the hand, looking along the approach) is
brought straight above the tray's centre, ``look_height_m`` above its floor (and at least
:data:`MIN_RANGE_ABOVE_CONTENTS_M` above the tallest contents: the whole tray in view); frames are
requested for ``look_frames`` frames (at most ``look_timeout_s``); their points (world frame) come from
the camera directly, and the perception loop keeps these frames out of its tracks
(:meth:`~.perception_loop.PerceptionLoop.looking_elsewhere`). Over the cells of the tray's height map within ``arrived_search_m``
of the released object's footprint (walls excepted), the object **arrived** when the points
there rise more than ``seen_min_height_m`` above what was there before the release (the
tray's contents as known then, within a cell) over at least ``arrived_min_area_m2`` — and no
more than ``arrived_max_above_m`` above the released object's top (higher points are not
it lying in the tray: e.g. it hangs on a finger). Where the look cannot
see that region (out of view, no frame), nothing was seen arriving.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Optional

import numpy as np
from scipy import ndimage

from ...array_rows import rows_where
from ...exceptions import GraspPipelineError
from ...motion.exceptions import MotionError
from ...robot import description as rm
from ...robot.protocols import ContactAllowance
from .place_config import PlaceConfig
from .tray import TrayGrid

log = logging.getLogger("grasp_pipeline.grasp")

#: The camera stays at least this far above the tray's tallest contents [m] (its near range
#: is 0.12 m).
MIN_RANGE_ABOVE_CONTENTS_M = 0.15
#: The share of the search region a look must see to judge the arrival.
MIN_SEEN_FRACTION = 0.3


class PlaceNotSeen(GraspPipelineError):
    """The released object was not seen in the tray."""


@dataclass(frozen=True)
class ArrivalVerdict:
    """``placed``: the object was seen in the tray; ``new_area_m2``: the newly occupied area
    near where it was released; ``seen_fraction``: the share of that region the look saw."""

    placed: bool
    new_area_m2: float
    seen_fraction: float
    message: str


def arrival_verdict(grid: TrayGrid, before: np.ndarray, released: np.ndarray, top_m: float,
                    points_world: Optional[np.ndarray], cfg: PlaceConfig) -> ArrivalVerdict:
    """The verdict (module doc) from the look's points; ``before`` (nu, nv): the contents'
    heights above the floor before the release; ``released`` (nu, nv): the cells under the
    released object; ``top_m``: its top above the floor as released."""
    region = grid.dilate(released, cfg.arrived_search_m) & ~grid.wall_mask()
    n_region = max(1, int(np.count_nonzero(region)))
    seen_h = grid.heights(np.zeros((0, 3)) if points_world is None else points_world)
    seen = region & np.isfinite(seen_h)
    frac = float(np.count_nonzero(seen)) / n_region
    if frac < MIN_SEEN_FRACTION:
        return ArrivalVerdict(False, 0.0, frac, f"the camera saw only {100 * frac:.0f} % of where "
                              "the object was released: its arrival in the tray is not confirmed")
    # what stood within a cell of a point was there before (the models' edges are a cell coarse)
    before = ndimage.maximum_filter(np.asarray(before, float), size=3)
    h = np.nan_to_num(seen_h, nan=0.0)
    new = seen & (h > before + cfg.seen_min_height_m) & (h <= top_m + cfg.arrived_max_above_m)
    area = float(np.count_nonzero(new)) * grid.cell_m ** 2
    if area >= cfg.arrived_min_area_m2:
        return ArrivalVerdict(True, area, frac, f"seen in the tray ({area * 1e4:.1f} cm2 new)")
    return ArrivalVerdict(False, area, frac, (
        f"the object is not seen in the tray: {area * 1e4:.1f} cm2 of new contents within "
        f"{cfg.arrived_search_m * 1e3:.0f} mm of where it was released (at least "
        f"{cfg.arrived_min_area_m2 * 1e4:.1f} cm2 expected; {100 * frac:.0f} % of that region seen)"))


def look_pose(model, yaw_rad: float, at_xy, camera_z_m: float) -> np.ndarray:
    """The TCP pose that puts the camera at (``at_xy``, ``camera_z_m``) looking straight down,
    the closing axis at ``yaw_rad`` from world x."""
    T_tcp_cam = np.linalg.inv(rm.flange_T_tcp(model)) @ rm.flange_T_camera(model)
    y = np.array([np.cos(yaw_rad), np.sin(yaw_rad), 0.0])
    z = np.array([0.0, 0.0, -1.0])
    R = np.column_stack([np.cross(y, z), y, z])
    off = R @ T_tcp_cam[:3, 3]
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = [at_xy[0] - off[0], at_xy[1] - off[1], camera_z_m - off[2]]
    return T


def look_into_tray(action, at_xy, contents_top_m: float):
    """Task: move the camera above ``at_xy`` (see the module doc; the closing axis turned as
    now, else a quarter or half turn further; from where the arm is when none of these can
    be planned) and return the points of the frames seen there, (N, 3) world, or None when
    no frame came."""
    cfg: PlaceConfig = action.place_config
    motion, robot, loop = action.motion, action.robot, action.loop
    floor_z = float(action.work_cell.tray_center_m[2])
    cam_z = floor_z + max(cfg.look_height_m, contents_top_m + MIN_RANGE_ABOVE_CONTENTS_M)
    y_now = robot.tcp_pose()[:3, 1]
    yaw = float(np.arctan2(y_now[1], y_now[0]))
    errors = []
    for turn in (0.0, 0.5 * np.pi, -0.5 * np.pi, np.pi):
        try:
            traj = motion.plan_pose(look_pose(motion.planner.model, yaw + turn, at_xy, cam_z))
        except MotionError as exc:
            errors.append(str(exc))
            continue
        try:
            yield from motion.execute("tray_look", traj, ContactAllowance.FINGERS)
        except GraspPipelineError as exc:
            errors.append(str(exc))
            motion.sync()
        break
    else:
        log.warning("could not move the camera above the tray (%s); looking from here", errors[0])
    return (yield from _frames_points(action.rt, robot, loop, cfg))


def _frames_points(rt, robot, loop, cfg: PlaceConfig):
    """Task: request frames until ``look_frames`` arrived (or ``look_timeout_s``); the points
    of those frames (None: none came). The perception loop keeps them out of its tracks (they
    show the tray, not the table)."""
    seen: list = []

    def listen(frame) -> None:
        seen.append(np.asarray(frame.points_world, float).reshape(-1, 3))

    t_end = robot.time_s + cfg.look_timeout_s
    robot.add_frame_listener(listen)
    try:
        with loop.looking_elsewhere(), rt.looking():
            while len(seen) < cfg.look_frames and robot.time_s < t_end:
                yield
    finally:
        robot.remove_frame_listener(listen)
    if not seen:
        log.warning("no camera frame while looking into the tray")
        return None
    pts = np.vstack(seen)
    finite = np.isfinite(pts[:, 0])  # column by column: the same rows, several times faster
    finite &= np.isfinite(pts[:, 1])
    finite &= np.isfinite(pts[:, 2])
    return rows_where(pts, finite)
