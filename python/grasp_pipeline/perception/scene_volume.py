"""The scene volume: the depth frames the arm takes, accumulated into one occupancy grid.

A voxel grid over a fixed world box (``config/volume.yaml``: by default the simulated table
top from 2 cm below it to 30 cm above, 5 mm voxels, 1.2 M voxels, 4.9 MB) in which every
integrated depth frame carves free space along its rays and marks the measured surfaces
occupied (log-odds occupancy, updated projectively in the C++ core: ``_core.SceneVolume``).
Each place is then :data:`FREE`, :data:`OCCUPIED`, :data:`UNKNOWN` (no camera has seen it)
or :data:`OUTSIDE` the box (nothing is known there; treat it as unknown unless you know better,
e.g. below the table).

Which frames: :meth:`SceneVolume.offer` integrates a frame when the camera moved
(``volume_integrate_moved_m`` / ``volume_integrate_turned_deg``) since the last integrated
frame, and otherwise every ``volume_integrate_every_frames``-th frame: frames from a camera
standing still repeat each other (5 mm voxels, 2 mm noise), while a static camera still sees
a scene that changed in front of it. A 640 x 480 frame costs ~7 ms of one core (measured on
the reference view; ``stats``).

Forgetting: objects move when a grasp is attempted — the target leaves (or is pushed), and
the hand may nudge its neighbours. Frames taken later carve the emptied space wherever they
see it, but a place no later frame sees would keep its old state for ever; so after each
attempt :meth:`SceneVolume.forget_after_attempt` forgets (makes UNKNOWN again) the column
over the target's box grown by ``volume_forget_margin_m`` (``volume_forget: target``), everything (``all``) or
nothing (``none``).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from .. import _core
from .volume_config import FORGET_ALL, FORGET_NONE, VolumeConfig

#: Voxel states (the int8 codes of :meth:`SceneVolume.classify`).
UNKNOWN: int = _core.VOXEL_UNKNOWN
FREE: int = _core.VOXEL_FREE
OCCUPIED: int = _core.VOXEL_OCCUPIED
OUTSIDE: int = _core.VOXEL_OUTSIDE


def core_params(config: VolumeConfig) -> "_core.SceneVolumeParams":
    """The C++ parameters of ``config``."""
    p = _core.SceneVolumeParams()
    p.box_min_m = np.asarray(config.volume_box_min_m, float)
    p.box_max_m = np.asarray(config.volume_box_max_m, float)
    p.voxel_m = config.volume_voxel_m
    p.truncation_m = config.volume_truncation_m
    p.logodds_hit, p.logodds_miss = config.volume_logodds_hit, config.volume_logodds_miss
    p.logodds_min, p.logodds_max = config.volume_logodds_min, config.volume_logodds_max
    return p


@dataclass(frozen=True)
class CameraModel:
    """A pinhole camera: intrinsics ``K`` (3, 3) and image size [px]."""

    K: np.ndarray
    width_px: int
    height_px: int


@dataclass
class VolumeStats:
    """Frames offered / integrated and the CPU time integrating them took."""

    frames_offered: int = 0
    frames_integrated: int = 0
    integrate_cpu_s: float = 0.0
    forgotten: list = field(default_factory=list)  # what each forget_after_attempt forgot


class SceneVolume:
    """The scene's occupancy grid (see the module doc); one per run."""

    def __init__(self, config: Optional[VolumeConfig] = None) -> None:
        self.config = config or VolumeConfig()
        self.core = _core.SceneVolume(core_params(self.config))
        self.camera: Optional[CameraModel] = None  # the camera of the latest integrated frame
        self.stats = VolumeStats()
        self._last_T: Optional[np.ndarray] = None
        self._since_integrated = 0

    # ---- frames -------------------------------------------------------------------
    def integrate(self, depth: np.ndarray, K: np.ndarray, T_world_camera: np.ndarray) -> "_core.VolumeIntegration":
        """Integrate one depth image (H, W) [m along the optical axis, NaN: invalid] taken
        with intrinsics ``K`` from the optical frame ``T_world_camera`` (4, 4)."""
        c0 = time.thread_time()
        out = self.core.integrate(depth, K, T_world_camera, self.config.volume_max_range_m)
        self.stats.integrate_cpu_s += time.thread_time() - c0
        self.stats.frames_integrated += 1
        depth = np.asarray(depth)
        self.camera = CameraModel(np.array(K, dtype=float), int(depth.shape[1]), int(depth.shape[0]))
        self._last_T = np.array(T_world_camera, dtype=float)
        self._since_integrated = 0
        return out

    def offer(self, frame) -> Optional["_core.VolumeIntegration"]:
        """Integrate ``frame`` (``depth``, ``K``, ``T_world_camera``) when the policy of the
        module doc wants it; None when it is skipped."""
        self.stats.frames_offered += 1
        self._since_integrated += 1
        T = np.asarray(frame.T_world_camera, dtype=float)
        if self._last_T is not None and not self._moved(T) \
                and self._since_integrated < self.config.volume_integrate_every_frames:
            return None
        return self.integrate(frame.depth, frame.K, T)

    def _moved(self, T: np.ndarray) -> bool:
        last = self._last_T
        shift = float(np.linalg.norm(T[:3, 3] - last[:3, 3]))
        cos = np.clip((np.trace(last[:3, :3].T @ T[:3, :3]) - 1.0) / 2.0, -1.0, 1.0)
        return shift >= self.config.volume_integrate_moved_m or \
            float(np.degrees(np.arccos(cos))) >= self.config.volume_integrate_turned_deg

    # ---- queries ------------------------------------------------------------------
    def classify(self, points: np.ndarray) -> np.ndarray:
        """(N,) int8 state of each world point (N, 3) [m]."""
        return self.core.classify(points)

    def not_free(self, points: np.ndarray) -> np.ndarray:
        """(N,) True where no camera has seen the point free (unknown, occupied or outside)."""
        return self.core.classify(np.asarray(points, dtype=float).reshape(-1, 3)) != FREE

    def occupied_centres(self, box_min, box_max) -> np.ndarray:
        """(M, 3) centres of the occupied voxels in the world box [m]."""
        return self.core.occupied_centres(box_min, box_max)

    def states_in_box(self, box_min, box_max) -> tuple[np.ndarray, np.ndarray]:
        """(centres (M, 3), states (M,) int8) of every voxel in the world box."""
        return self.core.states_in_box(box_min, box_max)

    def count_states(self, box_min, box_max) -> "_core.VolumeCounts":
        return self.core.count_states(box_min, box_max)

    def visible(self, points: np.ndarray, T_world_camera: np.ndarray, min_range_m: float,
                camera: Optional[CameraModel] = None) -> np.ndarray:
        """(N,) bool: which points a camera (default: the one integrated last) at
        ``T_world_camera`` would see, unoccluded by OCCUPIED voxels, between ``min_range_m``
        and ``volume_max_range_m``. Raises ValueError before any frame without ``camera``."""
        cam = camera or self.camera
        if cam is None:
            raise ValueError("visible: no camera model yet (integrate a frame first or pass camera=)")
        return self.core.visible(points, cam.K, cam.width_px, cam.height_px, T_world_camera,
                                 float(min_range_m), self.config.volume_max_range_m)

    @property
    def voxel_m(self) -> float:
        return self.config.volume_voxel_m

    @property
    def memory_bytes(self) -> int:
        return int(self.core.memory_bytes)

    # ---- forgetting ---------------------------------------------------------------
    def reset(self) -> None:
        """Forget everything."""
        self.core.reset()
        self._last_T = None

    def forget_box(self, box_min, box_max) -> None:
        """Forget the voxels in the world box [m] (UNKNOWN again)."""
        self.core.reset_box(box_min, box_max)
        self._last_T = None  # the next frame is integrated whatever its pose

    def forget_after_attempt(self, center, R, extents) -> None:
        """After a grasp attempt on the object whose box is (``center``, ``R``, ``extents``)
        (world, full extents [m]): forget what ``volume_forget`` says (module doc)."""
        policy = self.config.volume_forget
        if policy == FORGET_NONE:
            return
        if policy == FORGET_ALL:
            self.reset()
            self.stats.forgotten.append("all")
            return
        half = 0.5 * np.abs(np.asarray(R, float)) @ np.asarray(extents, float)  # the box's AABB
        pad = half + self.config.volume_forget_margin_m
        c = np.asarray(center, float)
        lo, hi = c - pad, c + pad
        lo[2], hi[2] = self.core.box_min_m[2], self.core.box_max_m[2]  # the whole column
        self.forget_box(lo, hi)
        self.stats.forgotten.append([lo.tolist(), hi.tolist()])
