"""The one definition of what a policy observes and commands in the simulator.

``record`` (the datasets) and the environment (``grasp_pipeline/PickPlace-v0``) both go through
:class:`ControlInterface`, so a dataset's frames and the environment's observations and actions
cannot drift apart:

* :meth:`ControlInterface.observation` — a dict whose keys, shapes, dtypes and units are the
  dataset's ``observation.*`` features (:func:`grasp_pipeline.dataset.features.dataset_features`):
  the wrist and scene camera RGB images (``observation.images.<camera>``, (H, W, 3) uint8),
  with ``depth`` their depth images (``observation.depth.<camera>``, (H, W, 1) float32 [m], 0 =
  nothing within ``depth_max_m``), ``observation.state`` (the 7 measured joints [rad] and the
  measured finger gap [m]) and ``observation.ee_pose`` (TCP position [m] and quaternion x, y, z, w);
* :meth:`ControlInterface.apply` — one ``action`` (the dataset's ``action``: 7 joint position
  targets [rad] and the finger gap target [m]) for one control period at the dataset's rate
  (``record.yaml`` ``record_fps_hz``): the joint reference ramps linearly from the previous
  action's targets to these over the period (its slope is the velocity feed-forward of the
  joint servos), so the targets are reached at the next frame's time and held after it; the
  gripper moves towards the gap at its own speed and squeezes with the simulator's default
  effort (``sim.yaml``). Joint targets outside the joint limits and gaps outside 0..0.08 m are
  clipped to them; anything not 8 finite numbers is refused (:class:`InvalidAction`).

Control periods are whole physics steps: period ``k`` ends at the step nearest to
``k / fps`` seconds after the start, so the control clock never drifts from the dataset's.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial.transform import Rotation

from ..dataset.camera_views import CAMERAS, RecordingViews
from ..dataset.config import RecordConfig
from ..exceptions import InputError
from ..robot.description import GRIPPER_MAX_WIDTH_M, PANDA_Q_MAX, PANDA_Q_MIN

STATE = "observation.state"
EE_POSE = "observation.ee_pose"
ACTION = "action"
#: Entries of an action: 7 joint targets and the finger gap target.
ACTION_SIZE = 8
ACTION_LOW = np.append(PANDA_Q_MIN, 0.0).astype(np.float32)
ACTION_HIGH = np.append(PANDA_Q_MAX, GRIPPER_MAX_WIDTH_M).astype(np.float32)


class InvalidAction(InputError):
    """An action that is not 8 finite numbers (7 joint targets [rad], a finger gap [m])."""


def image_key(camera: str) -> str:
    return f"observation.images.{camera}"


def depth_key(camera: str) -> str:
    return f"observation.depth.{camera}"


def pose_vector(T: np.ndarray) -> np.ndarray:
    """(7,) position [m] and quaternion (x, y, z, w) of a 4x4 pose."""
    T = np.asarray(T, dtype=float)
    return np.concatenate([T[:3, 3], Rotation.from_matrix(T[:3, :3]).as_quat()])


def pose_matrix(v) -> np.ndarray:
    """The 4x4 pose of a (7,) position + quaternion (x, y, z, w) vector."""
    v = np.asarray(v, dtype=float)
    T = np.eye(4)
    T[:3, :3] = Rotation.from_quat(v[3:7]).as_matrix()
    T[:3, 3] = v[:3]
    return T


def checked_action(action) -> np.ndarray:
    """``action`` as (8,) float64 within the limits; :class:`InvalidAction` if it is not 8
    finite numbers."""
    try:
        a = np.asarray(action, dtype=float).reshape(-1)
    except (TypeError, ValueError) as exc:
        raise InvalidAction(f"an action is {ACTION_SIZE} numbers (7 joint targets [rad], a finger "
                            f"gap [m]); got {type(action).__name__} ({exc})") from None
    if a.size != ACTION_SIZE:
        raise InvalidAction(f"an action is {ACTION_SIZE} numbers (7 joint targets [rad], a finger "
                            f"gap [m]); got shape {np.shape(action)}")
    if not np.all(np.isfinite(a)):
        raise InvalidAction(f"the action holds NaN or Inf: {a.tolist()}")
    return np.clip(a, ACTION_LOW.astype(float), ACTION_HIGH.astype(float))


class ControlInterface:
    """Observations and actions of one simulated world (a :class:`~grasp_pipeline.sim.world.SimWorld`
    just built: the control clock starts at its current time). Raises
    :class:`~grasp_pipeline.sim.exceptions.RenderUnavailable` where no GL context can exist."""

    def __init__(self, world, config: RecordConfig, depth: bool = False) -> None:
        self.world, self.config, self.depth = world, config, bool(depth)
        self.views = RecordingViews(world, config, self.depth)
        self.period_s = 1.0 / float(config.record_fps_hz)
        self.t0_s = float(world.time_s)
        self.steps = 0                  # control periods applied
        q_ref, _ = world.reference()
        self.targets = np.append(np.asarray(q_ref, float), float(world.gripper_target_m))

    def physics_steps(self, k: int) -> int:
        """Physics steps from the start to the end of control period ``k`` (1, 2, ...)."""
        return int(round(k * self.period_s / self.world.timestep_s))

    @property
    def next_time_s(self) -> float:
        """Simulated time at which the next action's targets are reached."""
        return self.t0_s + self.physics_steps(self.steps + 1) * self.world.timestep_s

    def apply(self, action) -> np.ndarray:
        """Apply ``action`` for one control period (see the module doc); returns the targets
        applied (clipped to the limits)."""
        a = checked_action(action)
        w = self.world
        n = self.physics_steps(self.steps + 1) - self.physics_steps(self.steps)
        w.follow_trajectory(np.array([0.0, n * w.timestep_s]), np.vstack([self.targets[:7], a[:7]]))
        w.set_gripper(float(a[7]))
        w.step(n)
        self.targets = a
        self.steps += 1
        return a

    def observation(self) -> dict:
        """The observation now (see the module doc)."""
        import mujoco

        w = self.world
        # the rendered bodies, the TCP and the joints all of this instant (after a physics step
        # MuJoCo's derived poses are those of the step's start); no effect on the dynamics
        mujoco.mj_kinematics(w.model, w.data)
        mujoco.mj_camlight(w.model, w.data)
        images, depths = self.views()
        obs = {image_key(c): images[c] for c in CAMERAS}
        if self.depth:
            obs.update({depth_key(c): depths[c][..., None] for c in CAMERAS})
        obs[STATE] = np.append(w.q, w.finger_gap_m).astype(np.float32)
        obs[EE_POSE] = pose_vector(w.tcp_pose()).astype(np.float32)
        return obs

    def close(self) -> None:
        self.views.close()


def control_steps(time_limit_s: float, fps_hz: int) -> int:
    """Control periods within ``time_limit_s`` at ``fps_hz``."""
    return max(1, int(math.ceil(time_limit_s * fps_hz - 1e-9)))
