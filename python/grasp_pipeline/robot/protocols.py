"""What the pipeline needs from a robot: four small protocols and the clock that paces them.

Perception, motion and orchestration talk to the robot only through these (structural
typing: any object with these members qualifies). ``grasp_pipeline.sim.world.SimWorld``
implements all of them for the simulated Panda; the adapter of a real robot implements the same
members and runs with ``grasp_pipeline.app.run_robot`` — nothing above them changes
(docs/real_robot.md, ``examples/own_robot``). Tests drive the grasp action with small fakes.

Units: joints in rad (rad/s), lengths in m, forces in N, times in s.
"""

from __future__ import annotations

import enum
from typing import Callable, ContextManager, Optional, Protocol, runtime_checkable

import numpy as np

from .frame import Frame


class ContactAllowance(enum.Enum):
    """Which robot contacts a motion expects (everything else is unexpected).

    ``NONE``: any contact of the robot with anything stops the motion (free-space motions).
    ``FINGERS``: the fingers may touch objects (approach, closing, releasing), never fixtures.
    ``HELD_OBJECT``: the object between the fingers may touch any part of the hand (carrying:
    it can tilt against the palm); every other contact is unexpected.
    """

    NONE = "none"
    FINGERS = "fingers"
    HELD_OBJECT = "held_object"


@runtime_checkable
class Clock(Protocol):
    """Time of the robot's control loop. ``step`` advances it by one control period (the
    simulator steps its physics; a real driver would wait for the next control cycle)."""

    @property
    def time_s(self) -> float: ...

    @property
    def timestep_s(self) -> float: ...

    def step(self, n: int = 1) -> None: ...


@runtime_checkable
class Arm(Protocol):
    """A 7-joint arm under joint position control."""

    @property
    def q(self) -> np.ndarray:
        """Measured joint positions (7,) [rad]."""

    @property
    def qd(self) -> np.ndarray:
        """Measured joint velocities (7,) [rad/s]."""

    def follow_trajectory(self, t_s: np.ndarray, q: np.ndarray, qd: Optional[np.ndarray] = None,
                          start_time_s: Optional[float] = None) -> float:
        """Start following a timed joint trajectory (non-blocking); returns its end time [s]."""

    def reference(self) -> tuple[np.ndarray, np.ndarray]:
        """The joint reference (q, qd) being tracked now."""

    def hold(self, q: Optional[np.ndarray] = None) -> None:
        """Drop the trajectory and hold ``q`` (default: where the arm is)."""

    def tcp_pose(self) -> np.ndarray:
        """World pose (4x4) of the TCP now (z = approach, y = closing axis)."""


@runtime_checkable
class Gripper(Protocol):
    """A parallel gripper with coupled fingers: command a gap and a force; read the gap."""

    @property
    def finger_gap_m(self) -> float:
        """Measured distance between the finger pads [m]."""

    @property
    def finger_speed_mps(self) -> float:
        """Speed of one finger [m/s], > 0 opening, < 0 closing."""

    @property
    def gripper_force_N(self) -> float:
        """Squeeze force the gripper exerts now [N] (>= 0)."""

    def set_gripper(self, width_m: float, effort_N: Optional[float] = None,
                    speed_mps: Optional[float] = None) -> None:
        """Command the finger gap (non-blocking) with a force limit."""


@runtime_checkable
class Camera(Protocol):
    """The eye-in-hand depth camera: frames carry the camera pose at the instant of capture.

    Frames on demand: the camera delivers frames (at its rate) only while at least one
    request is open — ``with camera.request_frames(): ...`` around every phase in which a
    consumer looks (rough view, scan dwell, the views before and after a grasp). A camera
    may also deliver frames continuously; consumers must not rely on frames they did not
    request. :attr:`looking_time_s` is the looking clock liveness is judged on."""

    def camera_pose(self) -> np.ndarray:
        """World pose (4x4) of the optical frame now."""

    def add_frame_listener(self, listener: Callable[[Frame], None]) -> None:
        """Call ``listener(frame)`` for every frame the camera delivers."""

    def remove_frame_listener(self, listener: Callable[[Frame], None]) -> None: ...

    def request_frames(self) -> ContextManager[None]:
        """Frames are wanted while this context is open (requests nest, counted)."""

    @property
    def looking_time_s(self) -> float:
        """Seconds of the robot's clock during which frames were requested (monotonic)."""


@runtime_checkable
class ContactMonitor(Protocol):
    """The arm's collision reflex: contacts that a motion did not expect."""

    def unexpected_contacts(self, allowance: ContactAllowance) -> list[str]:
        """Human-readable descriptions of the contacts not covered by ``allowance`` now."""


@runtime_checkable
class Robot(Clock, Arm, Gripper, Camera, ContactMonitor, Protocol):
    """Everything at once (``SimWorld`` is one)."""


def missing_members(robot: object, protocol: type = Robot) -> list[str]:
    """The members of ``protocol`` (default: all of :class:`Robot`) that ``robot`` lacks."""
    names = sorted({n for cls in protocol.__mro__ if getattr(cls, "_is_protocol", False)
                    and cls is not Protocol for n in vars(cls) if not n.startswith("_")})
    return [n for n in names if not hasattr(robot, n)]
