"""One recorded episode (one pick): its frames at the recording rate and its outcome.

The arrays of :class:`Episode` (``T`` frames):

* ``state`` (T, 8): the 7 measured arm joints [rad] and the measured finger gap [m];
* ``ee_pose`` (T, 7): the TCP's world position [m] and orientation quaternion (x, y, z, w);
* ``action`` (T, 8): the 7 joint position targets [rad] and the commanded finger gap [m]
  that the controller is given at the *next* frame's time — what the expert commanded the
  arm to reach over the interval from frame i to frame i+1 (the last frame: its own targets);
* ``action_ee_delta`` (T, 7): the TCP's motion from frame i to frame i+1 (position change
  [m] and rotation vector of ``R_{i+1} R_i^T`` [rad], world frame) and the commanded gap [m];
  zero motion on the last frame;
* ``images``: camera name -> (T, H, W, 3) uint8; ``depths``: camera name -> (T, H, W) float32 [m].

Episodes travel from the worker that records them to the parent that writes the dataset as
one ``.npz`` (arrays) plus its outcome in the worker's record (:meth:`Episode.outcome`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

import numpy as np

#: Names of the state / action vector entries (the dataset's feature ``names``).
JOINT_NAMES = tuple(f"joint{i}" for i in range(1, 8))
STATE_NAMES = JOINT_NAMES + ("finger_gap_m",)
ACTION_NAMES = tuple(f"{j}_target" for j in JOINT_NAMES) + ("gripper_gap_target_m",)
EE_POSE_NAMES = ("x_m", "y_m", "z_m", "qx", "qy", "qz", "qw")
EE_DELTA_NAMES = ("dx_m", "dy_m", "dz_m", "drx_rad", "dry_rad", "drz_rad", "gripper_gap_target_m")

_ARRAYS = ("time_s", "state", "ee_pose", "action", "action_ee_delta")


@dataclass
class Episode:
    """A pick's frames and outcome (see the module doc for the arrays)."""

    task: str
    success: bool
    failed_stage: str
    message: str
    object: Optional[str]
    time_s: np.ndarray
    state: np.ndarray
    ee_pose: np.ndarray
    action: np.ndarray
    action_ee_delta: np.ndarray
    images: dict = field(default_factory=dict)
    depths: dict = field(default_factory=dict)

    @property
    def length(self) -> int:
        return int(len(self.time_s))

    def outcome(self) -> dict:
        """The JSON-able outcome (no arrays)."""
        return {"task": self.task, "success": bool(self.success), "failed_stage": self.failed_stage,
                "message": self.message, "object": self.object, "length": self.length}

    def save(self, path: Path) -> None:
        """Write the arrays to ``path`` (``.npz``, compressed)."""
        arrays = {k: getattr(self, k) for k in _ARRAYS}
        arrays.update({f"image.{k}": v for k, v in self.images.items()})
        arrays.update({f"depth.{k}": v for k, v in self.depths.items()})
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(path.name + ".part.npz")
        np.savez_compressed(tmp, **arrays)
        tmp.replace(path)

    @classmethod
    def load(cls, path: Path, outcome: dict) -> "Episode":
        """The episode saved at ``path`` with its ``outcome`` (as :meth:`outcome` gave)."""
        with np.load(path) as z:
            arrays = {k: z[k] for k in _ARRAYS}
            images = {k.split(".", 1)[1]: z[k] for k in z.files if k.startswith("image.")}
            depths = {k.split(".", 1)[1]: z[k] for k in z.files if k.startswith("depth.")}
        return cls(task=outcome["task"], success=bool(outcome["success"]),
                   failed_stage=outcome.get("failed_stage") or "", message=outcome.get("message") or "",
                   object=outcome.get("object"), images=images, depths=depths, **arrays)
