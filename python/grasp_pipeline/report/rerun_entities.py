"""The entities of a run's Rerun recording: their paths and how each is logged.

Every function takes the ``rerun`` module (``rr``, imported by the caller: the SDK is an
optional extra) and a ``RecordingStream`` whose time is already set. Paths (world frame: x
forward, z up, metres):

========================================  =====================================================
``world/cloud/objects``                   Points3D, object points (red) of a perceived frame
``world/cloud/environment``               Points3D, environment points (blue)
``world/objects``                         Boxes3D, one box per track, label ``#tid quality``
``world/camera``                          Transform3D, the camera optical frame at capture
``world/camera/image``                    Pinhole (intrinsics, RDF: x right, y down, z forward)
``world/camera/image/rgb``                the RGB image (JPEG, or raw pixels)
``world/camera/image/depth``              DepthImage, uint16 millimetres (0 = no return)
``world/grasps/candidates``               Arrows3D, each proposed grasp's approach
``world/grasps/chosen``                   LineStrips3D, the planned grasp as an open gripper
``world/tcp``                             Transform3D, the TCP (sampled at the state rate)
``world/paths/planned``                   LineStrips3D, the TCP path of the latest plan
``world/paths/executed``                  LineStrips3D, the TCP path so far, one strip a motion
``timeline/stages``                       TextLog, each stage (``rough_view_done``, ``PRE_GRASP``)
``timeline/plans``                        TextLog, each motion planned (kind, method, times)
``timeline/picks``                        TextLog, each pick's outcome
``plots/finger_gap_mm``                   Scalars, the finger gap
``plots/perception_ms``                   Scalars, the core's time per frame
========================================  =====================================================
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np
from scipy.spatial.transform import Rotation

from . import rerun_geometry as geo

WORLD = "world"
CLOUD_OBJECTS = "world/cloud/objects"
CLOUD_ENVIRONMENT = "world/cloud/environment"
OBJECT_BOXES = "world/objects"
CAMERA = "world/camera"
CAMERA_IMAGE = "world/camera/image"
CAMERA_RGB = "world/camera/image/rgb"
CAMERA_DEPTH = "world/camera/image/depth"
GRASPS = "world/grasps"
GRASP_CANDIDATES = "world/grasps/candidates"
GRASP_CHOSEN = "world/grasps/chosen"
TCP = "world/tcp"
PATH_PLANNED = "world/paths/planned"
PATH_EXECUTED = "world/paths/executed"
STAGES = "timeline/stages"
PLANS = "timeline/plans"
PICKS = "timeline/picks"
FINGER_GAP = "plots/finger_gap_mm"
PERCEPTION_MS = "plots/perception_ms"

#: Drawing sizes [m] (radii of points and lines, length of the TCP axes, image plane distance).
POINT_RADIUS_M = 0.002
LINE_RADIUS_M = 0.002
TCP_AXIS_M = 0.05
IMAGE_PLANE_M = 0.1


def log_static(rr, rec) -> None:
    """The world's axes (z up) and the series' names."""
    rec.log(WORLD, rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True)
    rec.log(FINGER_GAP, rr.SeriesLines(names="finger gap [mm]"), static=True)
    rec.log(PERCEPTION_MS, rr.SeriesLines(names="perception [ms/frame]"), static=True)


def log_cloud(rr, rec, objects: np.ndarray, environment: np.ndarray) -> None:
    rec.log(CLOUD_OBJECTS, rr.Points3D(objects, colors=[geo.OBJECT_RGB], radii=POINT_RADIUS_M))
    rec.log(CLOUD_ENVIRONMENT, rr.Points3D(environment, colors=[geo.ENVIRONMENT_RGB],
                                           radii=POINT_RADIUS_M))


def log_boxes(rr, rec, boxes: geo.BoxBatch) -> None:
    rec.log(OBJECT_BOXES, rr.Boxes3D(centers=boxes.centers, half_sizes=boxes.half_sizes,
                                     quaternions=boxes.quaternions_xyzw, labels=boxes.labels,
                                     colors=boxes.colors, show_labels=True))


def log_camera(rr, rec, frame, jpeg_quality: int, pinhole_logged: bool) -> None:
    """The camera at its capture pose with its images (``frame``: ``robot.frame.Frame``);
    the intrinsics once (``pinhole_logged`` False)."""
    T = np.asarray(frame.T_world_camera, dtype=float)
    rec.log(CAMERA, rr.Transform3D(translation=T[:3, 3], mat3x3=T[:3, :3]))
    if not pinhole_logged:
        rec.log(CAMERA_IMAGE, rr.Pinhole(image_from_camera=np.asarray(frame.K, dtype=float),
                                         resolution=[frame.width, frame.height],
                                         camera_xyz=rr.ViewCoordinates.RDF,
                                         image_plane_distance=IMAGE_PLANE_M), static=True)
    if frame.rgb is not None:
        image = rr.Image(np.asarray(frame.rgb, dtype=np.uint8))
        rec.log(CAMERA_RGB, image.compress(jpeg_quality=jpeg_quality) if jpeg_quality > 0 else image)
    rec.log(CAMERA_DEPTH, rr.DepthImage(geo.depth_mm(frame.depth), meter=1000.0))


def log_grasps(rr, rec, candidates: Sequence, chosen) -> None:
    """Candidates as arrows labelled by rank and width; the chosen one as a gripper (cleared
    when no candidate could be planned)."""
    origins, vectors = geo.approach_arrows(candidates)
    labels = [f"{k + 1}: {float(g.width_m) * 1e3:.0f} mm" for k, g in enumerate(candidates)]
    rec.log(GRASP_CANDIDATES, rr.Arrows3D(origins=origins, vectors=vectors, labels=labels,
                                          colors=[geo.CANDIDATE_RGB], radii=LINE_RADIUS_M))
    if chosen is None:
        rec.log(GRASP_CHOSEN, rr.Clear(recursive=False))
        return
    rec.log(GRASP_CHOSEN, rr.LineStrips3D(geo.gripper_strips(candidates[chosen]),
                                          colors=[geo.CHOSEN_RGB], radii=LINE_RADIUS_M,
                                          labels=[f"chosen: candidate {chosen + 1}"]))


def clear_grasps(rr, rec) -> None:
    rec.log(GRASPS, rr.Clear(recursive=True))


def send_tcp(rr, timeline: str, rec, times_s: np.ndarray, poses: np.ndarray) -> None:
    """TCP poses (N, 4, 4) at simulated times (N,), as columns (one call for many samples)."""
    poses = np.asarray(poses, dtype=float).reshape(-1, 4, 4)
    quats = Rotation.from_matrix(poses[:, :3, :3]).as_quat()
    rec.send_columns(TCP, indexes=[rr.TimeColumn(timeline, duration=np.asarray(times_s, dtype=float))],
                     columns=rr.Transform3D.columns(translation=poses[:, :3, 3], quaternion=quats,
                                                    axis_length=np.full(len(poses), TCP_AXIS_M)))


def send_scalars(rr, timeline: str, rec, entity: str, times_s: np.ndarray, values: np.ndarray) -> None:
    """A scalar series' samples at simulated times, as columns."""
    rec.send_columns(entity, indexes=[rr.TimeColumn(timeline, duration=np.asarray(times_s, dtype=float))],
                     columns=rr.Scalars.columns(scalars=np.asarray(values, dtype=float)))


def log_path(rr, rec, entity: str, strips: Sequence[np.ndarray], rgb: tuple, label: str = "") -> None:
    strips = [np.asarray(s, dtype=np.float32) for s in strips if len(s) >= 2]
    if not strips:
        return
    rec.log(entity, rr.LineStrips3D(strips, colors=[rgb], radii=LINE_RADIUS_M,
                                    labels=[label] if label else None))


def log_text(rr, rec, entity: str, text: str, level: str = "INFO") -> None:
    rec.log(entity, rr.TextLog(text, level=level))


def default_blueprint(rrb: Any, time_s: float | None = None):
    """The viewer's layout: the 3-D world (left; the depth image is left out there, the
    perceived cloud is what it shows), the camera's RGB and depth, the series and the
    timeline's text logs (right); the time cursor at ``time_s`` when given."""
    camera = rrb.Horizontal(
        rrb.Spatial2DView(origin=CAMERA_IMAGE, contents=["$origin", CAMERA_RGB], name="camera RGB"),
        rrb.Spatial2DView(origin=CAMERA_IMAGE, contents=["$origin", CAMERA_DEPTH], name="depth"))
    return rrb.Blueprint(
        rrb.Horizontal(
            rrb.Spatial3DView(origin=WORLD, contents=["$origin/**", f"- {CAMERA_DEPTH}"], name="world"),
            rrb.Vertical(camera,
                         rrb.TimeSeriesView(origin="plots", name="finger gap, perception time"),
                         rrb.TextLogView(origin="timeline", name="stages, plans, picks")),
            column_shares=[3, 2]),
        rrb.BlueprintPanel(state="collapsed"), rrb.SelectionPanel(state="collapsed"),
        rrb.TimePanel(timeline="sim_time", duration_cursor=time_s))
