"""The adapter: the robot protocols of ``grasp_pipeline.robot.protocols`` on the toy hardware.

This is the file you write for your own robot (docs/real_robot.md): one object with the
clock, arm, gripper, camera and contact-monitor members, each mapped onto your drivers.
What it shows:

* **clock** — ``step()`` advances one control period and delivers the camera frames that are
  due. Here time is virtual (the toy runs as fast as it can); on a real robot ``step()`` waits
  for the next control cycle and reads the drivers.
* **arm** — a timed joint trajectory handed to the driver, joints and velocities read back,
  ``hold()`` stops the arm where it is, the TCP pose from the joints.
* **gripper** — width and force commands; gap, finger speed and force read back.
* **camera** — frames only while requested (counted), each built with ``Frame.from_depth``
  from the raw depth *times the depth scale* (metres), the stream's intrinsics and the camera
  pose at capture = flange pose (FK of the joints at capture) x the hand-eye calibration.
* **contact monitor** — the toy has no collision sensing: no unexpected contacts (a real arm
  maps its collision reflex here, e.g. libfranka's ``cartesian_contact`` flags).
"""

from __future__ import annotations

from contextlib import contextmanager
from typing import Callable, Iterator, Optional

import numpy as np

from grasp_pipeline.robot.frame import Frame
from grasp_pipeline.robot.protocols import ContactAllowance

from toy_hardware import ToyHardware

#: Control period of the adapter's clock [s] and the camera's frame rate [Hz].
TIMESTEP_S = 0.01
CAMERA_RATE_HZ = 15.0
DEFAULT_EFFORT_N = 40.0


class OwnRobot:
    """A :class:`grasp_pipeline.robot.protocols.Robot` on :class:`~toy_hardware.ToyHardware`.
    ``flange_T_camera``: the hand-eye calibration (the work-cell file's ``camera_mount``)."""

    def __init__(self, hardware: ToyHardware, flange_T_camera: np.ndarray) -> None:
        self.hw = hardware
        self.flange_T_camera = np.asarray(flange_T_camera, float)
        self._listeners: list[Callable[[Frame], None]] = []
        self._requests = 0
        self._looking_s = 0.0
        self._next_frame_s = 0.0
        self._frames = 0

    # ---- clock --------------------------------------------------------------------------
    @property
    def time_s(self) -> float:
        return self.hw.time_s

    @property
    def timestep_s(self) -> float:
        return TIMESTEP_S

    def step(self, n: int = 1) -> None:
        for _ in range(int(n)):
            self.hw.tick(TIMESTEP_S)
            if self._requests:
                self._looking_s += TIMESTEP_S
                if self.time_s >= self._next_frame_s and self._listeners:
                    self._deliver(self.capture())

    # ---- arm ----------------------------------------------------------------------------
    @property
    def q(self) -> np.ndarray:
        return self.hw.arm.q.copy()

    @property
    def qd(self) -> np.ndarray:
        return self.hw.arm.qd.copy()

    def follow_trajectory(self, t_s: np.ndarray, q: np.ndarray, qd: Optional[np.ndarray] = None,
                          start_time_s: Optional[float] = None) -> float:
        t0 = self.time_s if start_time_s is None else float(start_time_s)
        t_abs = t0 + np.asarray(t_s, float)
        self.hw.arm.start_trajectory(t_abs, np.asarray(q, float))
        return float(t_abs[-1])

    def reference(self) -> tuple[np.ndarray, np.ndarray]:
        return self.hw.arm.target(self.time_s)

    def hold(self, q: Optional[np.ndarray] = None) -> None:
        self.hw.arm.stop(q)

    def tcp_pose(self) -> np.ndarray:
        return self.hw.tcp_pose()

    # ---- gripper ------------------------------------------------------------------------
    @property
    def finger_gap_m(self) -> float:
        return self.hw.gripper.width_m

    @property
    def finger_speed_mps(self) -> float:
        return self.hw.gripper.finger_speed_mps

    @property
    def gripper_force_N(self) -> float:
        return self.hw.gripper.force_N

    def set_gripper(self, width_m: float, effort_N: Optional[float] = None,
                    speed_mps: Optional[float] = None) -> None:
        self.hw.gripper.command(width_m, DEFAULT_EFFORT_N if effort_N is None else effort_N)

    # ---- camera -------------------------------------------------------------------------
    def camera_pose(self) -> np.ndarray:
        return self.hw.flange_pose() @ self.flange_T_camera

    def capture(self) -> Frame:
        """One frame: raw depth x depth scale = metres, the stream's intrinsics, the pose at
        capture. (Frame.from_depth refuses raw integer depth and a missing pose.)"""
        cam = self.hw.camera
        raw = self.hw.camera_image()  # (H, W) uint16, units of cam.depth_scale metres
        K = np.array([[cam.fx, 0.0, cam.ppx], [0.0, cam.fy, cam.ppy], [0.0, 0.0, 1.0]])
        depth_m = raw.astype(np.float32) * np.float32(cam.depth_scale)  # 0 (no return) becomes NaN
        return Frame.from_depth(depth_m, K, self.camera_pose(), self.time_s, index=self._frames, backend="toy")

    def _deliver(self, frame: Frame) -> None:
        self._frames += 1
        self._next_frame_s = self.time_s + 1.0 / CAMERA_RATE_HZ
        for listener in list(self._listeners):
            listener(frame)

    def add_frame_listener(self, listener: Callable[[Frame], None]) -> None:
        self._listeners.append(listener)

    def remove_frame_listener(self, listener: Callable[[Frame], None]) -> None:
        if listener in self._listeners:
            self._listeners.remove(listener)

    @contextmanager
    def request_frames(self) -> Iterator[None]:
        if self._requests == 0:  # the first frame one camera period after the last one at the earliest
            self._next_frame_s = max(self._next_frame_s, self.time_s)
        self._requests += 1
        try:
            yield
        finally:
            self._requests -= 1

    @property
    def looking_time_s(self) -> float:
        return self._looking_s

    # ---- contact monitor ----------------------------------------------------------------
    def unexpected_contacts(self, allowance: ContactAllowance) -> list[str]:
        return []
