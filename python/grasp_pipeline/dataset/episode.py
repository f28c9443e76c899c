"""One recorded episode: its frames at the recording rate and its outcome.

The arrays of :class:`Episode` (``T`` frames; frame ``i`` is the observation before the
``i``-th action and that action):

* ``state`` (T, 8): the 7 measured arm joints [rad] and the measured finger gap [m];
* ``ee_pose`` (T, 7): the TCP's world position [m] and orientation quaternion (x, y, z, w);
* ``action`` (T, 8): the 7 joint position targets [rad] and the finger gap target [m] applied
  from frame i to frame i+1 (reached at frame i+1's time: :mod:`grasp_pipeline.learning.interface`);
* ``action_ee_delta`` (T, 7): the TCP's motion from frame i to the next observation (position
  change [m] and rotation vector of ``R_{i+1} R_i^T`` [rad], world frame) and the gap target [m];
* ``images``: camera name -> (T, H, W, 3) uint8; ``depths``: camera name -> (T, H, W) float32 [m].

:func:`build_episode` makes one from the observations and actions of an environment episode
(:class:`.episode_recording.EpisodeRecording`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import numpy as np
from scipy.spatial.transform import Rotation

#: Names of the state / action vector entries (the dataset's feature ``names``).
JOINT_NAMES = tuple(f"joint{i}" for i in range(1, 8))
STATE_NAMES = JOINT_NAMES + ("finger_gap_m",)
ACTION_NAMES = tuple(f"{j}_target" for j in JOINT_NAMES) + ("gripper_gap_target_m",)
EE_POSE_NAMES = ("x_m", "y_m", "z_m", "qx", "qy", "qz", "qw")
EE_DELTA_NAMES = ("dx_m", "dy_m", "dz_m", "drx_rad", "dry_rad", "drz_rad", "gripper_gap_target_m")


@dataclass
class Episode:
    """An episode's frames and outcome (see the module doc for the arrays)."""

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


def ee_deltas(poses: np.ndarray, gaps: np.ndarray) -> np.ndarray:
    """(T, 7) TCP motion from each of the first T poses to the next (``poses``: (T+1, 7)) and
    the gap targets ``gaps`` (T,)."""
    rot = Rotation.from_quat(poses[:, 3:])
    delta = np.zeros((len(poses) - 1, 7))
    delta[:, :3] = poses[1:, :3] - poses[:-1, :3]
    delta[:, 3:6] = (rot[1:] * rot[:-1].inv()).as_rotvec()
    delta[:, 6] = gaps
    return delta


def build_episode(frames: list, last_obs: dict, outcome: dict, depth: bool = False) -> Episode:
    """The episode of ``frames`` — (time [s], observation, action applied) per step — whose
    last action led to ``last_obs``; ``outcome``: task, success, failed_stage, message, object."""
    from ..learning.interface import EE_POSE, STATE, depth_key, image_key
    from .camera_views import CAMERAS as cameras

    f32 = np.float32
    obs = [o for _, o, _ in frames]
    action = np.asarray([a for _, _, a in frames], dtype=float)
    poses = np.asarray([o[EE_POSE] for o in obs + [last_obs]], dtype=float)
    images = {c: np.stack([o[image_key(c)] for o in obs]) for c in cameras}
    depths = {c: np.stack([o[depth_key(c)][..., 0] for o in obs]) for c in cameras} if depth else {}
    return Episode(task=outcome["task"], success=bool(outcome["success"]),
                   failed_stage=outcome.get("failed_stage") or "", message=outcome.get("message") or "",
                   object=outcome.get("object"), time_s=np.asarray([t for t, _, _ in frames], dtype=np.float64),
                   state=np.asarray([o[STATE] for o in obs], dtype=f32), ee_pose=poses[:-1].astype(f32),
                   action=action.astype(f32), action_ee_delta=ee_deltas(poses, action[:, 7]).astype(f32),
                   images=images, depths=depths)
