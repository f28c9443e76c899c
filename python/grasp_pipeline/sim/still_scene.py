"""A render reused while nothing in view moves.

While the robot watches a table at rest (a rough view, a settle view, a probe's dwell), most
frames show the scene the previous render showed: no geom and not the camera moved by more
than a micrometre, far below the sensor's noise (2 mm at 0.4 m) and the width of a pixel
(about 1 mm at that range). Such a frame needs no new render: :class:`StillSceneCache` keeps the
clean images of the last render (depth with the invalid and grazing pixels masked, colour,
labels) with the poses they were rendered at, and hands them out again while every pose stays
within ``tolerance_m`` of those (positions in metres, rotation-matrix entries as metres at a
lever of 1 m); the frame still gets its own noise draws, so each frame stays one sample of
the sensor. A frame built from a kept render carries that render's camera pose (the image
and its pose belong together). ``tolerance_m`` = 0 renders every frame.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import mujoco
import numpy as np


@dataclass(frozen=True)
class CleanImages:
    """One render's clean images: ``depth`` (H, W) float32 [m] with NaN where invalid or
    grazing, ``invalid`` (H, W) bool (out of range), ``rgb`` (H, W, 3) uint8 or None, ``geoms``
    (H, W) int32 geom ids or None (labels off), and the camera pose they were rendered at."""

    T_world_camera: np.ndarray
    depth: np.ndarray
    invalid: np.ndarray
    rgb: Optional[np.ndarray]
    geoms: Optional[np.ndarray]


class StillSceneCache:
    """The last render and the poses it was rendered at (see the module doc)."""

    def __init__(self, tolerance_m: float) -> None:
        self.tolerance_m = float(tolerance_m)
        self._key: Optional[np.ndarray] = None
        self._images: Optional[CleanImages] = None
        self.renders = 0  # renders kept
        self.reused = 0   # frames that reused one

    @property
    def enabled(self) -> bool:
        return self.tolerance_m > 0.0

    @staticmethod
    def scene_key(data: mujoco.MjData, cam_id: int, passes: tuple[bool, ...] = ()) -> np.ndarray:
        """What a render depends on that can change: every geom's pose, the camera's and
        which images are wanted (``passes``: e.g. labels on, colour on; a switch renders anew)."""
        return np.concatenate([data.geom_xpos.ravel(), data.geom_xmat.ravel(),
                               data.cam_xpos[cam_id], data.cam_xmat[cam_id],
                               np.asarray(passes, dtype=float)])

    def lookup(self, key: np.ndarray) -> Optional[CleanImages]:
        """The kept images when no pose of ``key`` moved more than the tolerance since they
        were rendered, else None (render anew)."""
        if not self.enabled or self._key is None or len(key) != len(self._key):
            return None
        if float(np.max(np.abs(key - self._key))) > self.tolerance_m:
            return None
        self.reused += 1
        return self._images

    def keep(self, key: np.ndarray, images: CleanImages) -> None:
        """Keep ``images`` (rendered at the poses ``key``); the caller must not change them."""
        if self.enabled:
            self._key, self._images = key, images
            self.renders += 1

    def clear(self) -> None:
        self._key = self._images = None
