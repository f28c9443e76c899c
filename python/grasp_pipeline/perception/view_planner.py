"""Next views of an object's sides: camera poses around it, ranked by what they would reveal.

Candidates stand on spheres around the target's centre: ``side_view_distances_m`` away, at
``side_view_elevations_deg`` above the table and every ``side_view_azimuth_step_deg`` of
azimuth, each looking at the centre with the image upright (image x horizontal). A candidate
scores the number of the target's UNKNOWN shell voxels (:mod:`.side_coverage`) it would see:
inside its image and range, with no OCCUPIED voxel on the ray (a ray march through the
volume; unknown voxels on the way do not block). Candidates are returned best first (ties:
nearest the reference camera position, i.e. the shortest move); whether the arm reaches one
is the motion layer's question (:mod:`grasp_pipeline.orchestration.scanning.side_view`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from .scene_volume import CameraModel, SceneVolume
from .volume_config import VolumeConfig

#: At most this many unknown shell voxels are ray-marched per candidate (an even subsample).
MAX_SCORED_POINTS = 1500


@dataclass(frozen=True)
class ViewCandidate:
    """One camera pose (optical frame, 4x4 world) and what it would reveal."""

    T_world_camera: np.ndarray
    azimuth_deg: float
    elevation_deg: float
    distance_m: float
    seen: int = 0             # unknown shell voxels it would see (of the scored subsample, rescaled)
    seen_fraction: float = 0.0  # of the unknown shell voxels


def look_at(eye: np.ndarray, target: np.ndarray, up=(0.0, 0.0, 1.0)) -> np.ndarray:
    """Optical frame (x right, y down, z forward) at ``eye`` looking at ``target``, image x
    horizontal (perpendicular to ``up``)."""
    z = np.asarray(target, float) - np.asarray(eye, float)
    z /= np.linalg.norm(z)
    x = np.cross(z, np.asarray(up, float))
    if np.linalg.norm(x) < 1e-9:  # looking straight along up: any horizontal x
        x = np.cross(z, [0.0, 1.0, 0.0])
    x /= np.linalg.norm(x)
    T = np.eye(4)
    T[:3, 0], T[:3, 1], T[:3, 2], T[:3, 3] = x, np.cross(z, x), z, eye
    return T


def candidate_views(target: np.ndarray, config: VolumeConfig, up=(0.0, 0.0, 1.0)) -> list[ViewCandidate]:
    """Every candidate pose around ``target`` [m, world] (not scored)."""
    up = np.asarray(up, float) / np.linalg.norm(up)
    e1 = np.cross(up, [0.0, 1.0, 0.0]) if abs(up[0]) < 0.9 else np.cross(up, [0.0, 0.0, 1.0])
    e1 = -e1 / np.linalg.norm(e1)  # world +x for a vertical up
    e2 = np.cross(up, e1)
    out = []
    step = config.side_view_azimuth_step_deg
    for az in np.arange(0.0, 360.0 - 1e-9, step):
        a = np.radians(az)
        for el in config.side_view_elevations_deg:
            e = np.radians(el)
            direction = np.cos(e) * (np.cos(a) * e1 + np.sin(a) * e2) + np.sin(e) * up
            for d in config.side_view_distances_m:
                eye = np.asarray(target, float) + d * direction
                out.append(ViewCandidate(look_at(eye, target, up), float(az), float(el), float(d)))
    return out


def _subsample(points: np.ndarray, limit: int) -> tuple[np.ndarray, float]:
    """At most ``limit`` rows taken evenly, and the factor that scales counts back."""
    if len(points) <= limit:
        return points, 1.0
    idx = np.linspace(0, len(points) - 1, limit).round().astype(int)
    return points[idx], len(points) / float(limit)


def rank_views(volume: SceneVolume, unknown_points: np.ndarray, target: np.ndarray, config: VolumeConfig,
               reference_position: Optional[np.ndarray] = None, camera: Optional[CameraModel] = None,
               up=(0.0, 0.0, 1.0)) -> list[ViewCandidate]:
    """The candidates that would see any of ``unknown_points``, best first (module doc)."""
    pts, scale = _subsample(np.asarray(unknown_points, float).reshape(-1, 3), MAX_SCORED_POINTS)
    if len(pts) == 0:
        return []
    total = len(unknown_points)
    scored = []
    for c in candidate_views(target, config, up):
        seen = int(np.count_nonzero(volume.visible(pts, c.T_world_camera, config.side_view_min_range_m, camera)))
        if seen:
            n = int(round(seen * scale))
            scored.append(ViewCandidate(c.T_world_camera, c.azimuth_deg, c.elevation_deg, c.distance_m,
                                        n, min(1.0, n / total)))
    ref = None if reference_position is None else np.asarray(reference_position, float)

    def key(c: ViewCandidate):
        move = 0.0 if ref is None else float(np.linalg.norm(c.T_world_camera[:3, 3] - ref))
        return (-c.seen, move)

    return sorted(scored, key=key)
