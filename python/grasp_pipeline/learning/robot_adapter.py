"""The robot protocols of :mod:`grasp_pipeline.robot.protocols` on top of the learning
environment: the pipeline commands the robot only through ``env.step(action)``.

:class:`EnvRobot` is a :class:`~grasp_pipeline.robot.protocols.Robot` whose

* **clock** is the environment's control clock: ``step()`` sends one action — the 7 joints of
  the trajectory the arm follows, sampled where the action will be reached (the next control
  time), and the commanded finger gap — and advances one control period; ``time_s`` and
  ``timestep_s`` are the environment's;
* **arm and gripper** readings come from the observation (``observation.state``: joints and
  finger gap; ``observation.ee_pose``: the TCP) and from what the environment reports besides
  (``info``: joint velocities, finger speed, squeeze force); commands (``follow_trajectory``,
  ``hold``, ``set_gripper``) only change what the next actions will be;
* **camera and contact monitor** are the simulator's sensors (:class:`.sensors.SimSensors`),
  read-only, as ``run`` perceives.

When the environment ends the episode (``terminated`` or ``truncated``), ``step()`` raises
:class:`EpisodeEnded` (a ``BaseException``: the pipeline's own error handling lets it through).
"""

from __future__ import annotations

import logging
from typing import Callable, Optional

import numpy as np
from scipy.interpolate import CubicHermiteSpline, make_interp_spline

from ..robot.description import GRIPPER_MAX_WIDTH_M, PANDA_Q_MAX, PANDA_Q_MIN
from .interface import EE_POSE, STATE, pose_matrix

log = logging.getLogger(__name__)

#: How far outside the joint limits a trajectory point may lie (as the simulator allows) [rad].
LIMIT_SLACK_RAD = 1e-3


class EpisodeEnded(BaseException):
    """The environment ended the episode: ``terminated`` (the task is done) or ``truncated``."""

    def __init__(self, terminated: bool, info: dict) -> None:
        super().__init__("the task is done" if terminated else info.get("failure_reason", "truncated"))
        self.terminated, self.info = terminated, info


class JointReference:
    """A timed joint trajectory on absolute time: cubic Hermite with velocities, else linear;
    before its start it holds the first sample, after its end the last (zero velocity)."""

    def __init__(self, t_abs: np.ndarray, q: np.ndarray, qd: Optional[np.ndarray]) -> None:
        self.t, self.q = t_abs, q
        self.spline = self.rate = None
        if len(t_abs) > 1:
            self.spline = (make_interp_spline(t_abs, q, k=1, axis=0) if qd is None
                           else CubicHermiteSpline(t_abs, q, qd, axis=0))
            self.rate = self.spline.derivative()

    @property
    def end_time_s(self) -> float:
        return float(self.t[-1])

    def sample(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        if self.spline is None or t <= self.t[0]:
            return self.q[0].copy(), np.zeros(self.q.shape[1])
        if t >= self.t[-1]:
            return self.q[-1].copy(), np.zeros(self.q.shape[1])
        return np.asarray(self.spline(t)), np.asarray(self.rate(t))


def checked_trajectory(t_s, q, qd) -> tuple[np.ndarray, np.ndarray, Optional[np.ndarray]]:
    """(t, q, qd) as arrays, or ``ValueError`` saying what is wrong (as the simulator checks)."""
    t = np.asarray(t_s, dtype=float).reshape(-1)
    qq = np.asarray(q, dtype=float)
    if qq.ndim != 2 or qq.shape[1] != 7 or qq.shape[0] != t.shape[0] or t.size == 0:
        raise ValueError(f"need t_s (K,) and q (K, 7); got {t.shape} and {qq.shape}")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(qq))) or (t.size > 1 and np.any(np.diff(t) <= 0)):
        raise ValueError("trajectory times must be finite and strictly increasing, joints finite")
    if np.any((qq < PANDA_Q_MIN - LIMIT_SLACK_RAD) | (qq > PANDA_Q_MAX + LIMIT_SLACK_RAD)):
        raise ValueError("trajectory leaves the joint limits")
    qdd = None if qd is None else np.asarray(qd, dtype=float)
    if qdd is not None and (qdd.shape != qq.shape or not np.all(np.isfinite(qdd))):
        raise ValueError(f"qd must be finite with shape {qq.shape}, got {qdd.shape}")
    return t, qq, qdd


class EnvRobot:
    """See the module doc. ``env``: the (possibly wrapped) environment whose ``step`` the
    robot calls; ``obs``, ``info``: what its ``reset`` returned."""

    def __init__(self, env, obs: dict, info: dict) -> None:
        self.env = env
        base = env.unwrapped
        self.sensors = base.sensors
        self.timestep_s = float(base.control_period_s)
        self._next_time = lambda: float(base.interface.next_time_s)
        self._default_effort_N = float(base.settings.sim.gripper_default_effort_N)
        self._obs, self._info = obs, info
        self._traj: Optional[JointReference] = None
        self._capture_q: Optional[np.ndarray] = None
        self._hold_q = self.q.copy()
        self._gap_target = float(base.interface.targets[7])
        self._listeners: dict = {}
        self._warned = False
        self.ended: Optional[EpisodeEnded] = None
        self.steps = 0

    # ---- clock -----------------------------------------------------------------------
    @property
    def time_s(self) -> float:
        return float(self._info["time_s"])

    def action(self) -> np.ndarray:
        """The next action: the joint reference at the next control time, the gap target."""
        q, _ = self.reference(self._next_time())
        return np.append(q, self._gap_target).astype(np.float32)

    def step(self, n: int = 1) -> None:
        """Send ``n`` actions, one control period each; :class:`EpisodeEnded` when the
        environment ends the episode."""
        for _ in range(int(n)):
            if self.ended is not None:
                raise self.ended
            obs, _reward, terminated, truncated, info = self.env.step(self.action())
            self._obs, self._info = obs, info
            self.steps += 1
            if terminated or truncated:
                self.ended = EpisodeEnded(bool(terminated), info)
                raise self.ended

    # ---- arm --------------------------------------------------------------------------
    @property
    def q(self) -> np.ndarray:
        if self._capture_q is not None:  # inside a camera frame's delivery: the joints at capture
            return self._capture_q.copy()
        return np.asarray(self._obs[STATE][:7], dtype=float)

    @property
    def qd(self) -> np.ndarray:
        return np.asarray(self._info["joint_velocity"], dtype=float)

    def follow_trajectory(self, t_s, q, qd=None, start_time_s: Optional[float] = None) -> float:
        t, qq, qdd = checked_trajectory(t_s, q, qd)
        t0 = self.time_s if start_time_s is None else float(start_time_s)
        self._traj = JointReference(t + t0, qq, qdd)
        return self._traj.end_time_s

    def reference(self, t: Optional[float] = None) -> tuple[np.ndarray, np.ndarray]:
        t = self.time_s if t is None else float(t)
        if self._traj is None:
            return self._hold_q.copy(), np.zeros(7)
        return self._traj.sample(t)

    def hold(self, q: Optional[np.ndarray] = None) -> None:
        self._traj = None
        self._hold_q = self.q.copy() if q is None else np.asarray(q, dtype=float).reshape(7).copy()

    def trajectory_done(self) -> bool:
        return self._traj is None or self.time_s >= self._traj.end_time_s

    def tcp_pose(self) -> np.ndarray:
        return pose_matrix(self._obs[EE_POSE])

    # ---- gripper ----------------------------------------------------------------------
    @property
    def finger_gap_m(self) -> float:
        return float(self._obs[STATE][7])

    @property
    def finger_speed_mps(self) -> float:
        return float(self._info["finger_speed_mps"])

    @property
    def gripper_force_N(self) -> float:
        return float(self._info["gripper_force_N"])

    @property
    def gripper_target_m(self) -> float:
        return self._gap_target

    def set_gripper(self, width_m: float, effort_N: Optional[float] = None,
                    speed_mps: Optional[float] = None) -> None:
        """The gap of the next actions. The environment's gripper closes at its own speed and
        squeezes with its default effort: another ``effort_N`` is warned about once."""
        w = float(width_m)
        if not (np.isfinite(w) and 0.0 <= w <= GRIPPER_MAX_WIDTH_M + 1e-9):
            raise ValueError(f"gripper width must be within 0..{GRIPPER_MAX_WIDTH_M} m, got {width_m}")
        if effort_N is not None and abs(effort_N - self._default_effort_N) > 1e-9 and not self._warned:
            log.warning("the environment's gripper squeezes with %.0f N; the commanded %.0f N is not an "
                        "action (sim.gripper_default_effort_N sets it)", self._default_effort_N, effort_N)
            self._warned = True
        self._gap_target = min(w, GRIPPER_MAX_WIDTH_M)

    # ---- camera and contacts: the simulator's sensors, read-only -------------------------
    def camera_pose(self) -> np.ndarray:
        return self.sensors.camera_pose()

    def add_frame_listener(self, listener: Callable) -> None:
        def deliver(frame) -> None:
            self._capture_q = np.asarray(self.sensors.joint_positions(), dtype=float)
            try:
                listener(frame)
            finally:
                self._capture_q = None

        self._listeners[listener] = deliver
        self.sensors.add_frame_listener(deliver)

    def remove_frame_listener(self, listener: Callable) -> None:
        deliver = self._listeners.pop(listener, None)
        if deliver is not None:
            self.sensors.remove_frame_listener(deliver)

    def request_frames(self):
        return self.sensors.request_frames()

    @property
    def looking_time_s(self) -> float:
        return self.sensors.looking_time_s

    def unexpected_contacts(self, allowance) -> list[str]:
        return self.sensors.unexpected_contacts(allowance)

    # ---- the robot's fixed description (what build_system reads) -------------------------
    @property
    def model(self):
        return self.sensors.model

    @property
    def work_cell(self):
        return self.sensors.work_cell

    def close(self) -> None:
        """Nothing to free: the environment owns the simulator."""
        for listener in list(self._listeners):
            self.remove_frame_listener(listener)
