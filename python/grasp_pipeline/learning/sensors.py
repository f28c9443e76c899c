"""What the simulator offers a policy besides the observation, read-only: the eye-in-hand depth
camera (frames on request, as perception receives them), the contact monitor, and the robot's
fixed description (its model, for the camera's mounting; the work cell's fixtures).

The reference policy perceives through these as ``run`` does; it commands the robot only
through the environment's ``step(action)``. Nothing here moves the robot or the scene.
"""

from __future__ import annotations

from contextlib import contextmanager
from typing import Callable, Iterator

import numpy as np

from ..robot.protocols import ContactAllowance


class SimSensors:
    """The sensors of one simulated world (an environment's current episode)."""

    def __init__(self, world) -> None:
        self._world = world

    @property
    def model(self):
        """The robot and scene description (MuJoCo model: fixed, not the state)."""
        return self._world.model

    @property
    def work_cell(self):
        return self._world.work_cell

    def joint_positions(self) -> np.ndarray:
        """The arm's joints now [rad] (the joint state a camera frame is captured with)."""
        return self._world.q

    def camera_pose(self) -> np.ndarray:
        return self._world.camera_pose()

    def add_frame_listener(self, listener: Callable) -> None:
        self._world.add_frame_listener(listener)

    def remove_frame_listener(self, listener: Callable) -> None:
        self._world.remove_frame_listener(listener)

    @contextmanager
    def request_frames(self) -> Iterator[None]:
        with self._world.request_frames():
            yield

    @property
    def looking_time_s(self) -> float:
        return self._world.looking_time_s

    def unexpected_contacts(self, allowance: ContactAllowance) -> list[str]:
        return self._world.unexpected_contacts(allowance)
