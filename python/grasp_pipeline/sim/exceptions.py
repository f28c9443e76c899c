"""Errors raised by the simulator package (all derive from GraspPipelineError)."""

from __future__ import annotations

from ..exceptions import GraspPipelineError


class SimError(GraspPipelineError):
    """Base class of the simulator's errors."""


class ModelError(SimError):
    """The MuJoCo model cannot be built or lacks an element the simulator needs."""


class SceneError(SimError, ValueError):
    """A scene specification is invalid or cannot be generated (e.g. objects do not fit)."""


class RenderError(SimError):
    """No depth backend could be started, or the requested one failed."""


class TrajectoryError(SimError, ValueError):
    """A joint trajectory handed to the simulator is malformed (shapes, times, limits)."""


class GripperError(SimError, ValueError):
    """A gripper command is out of range (width beyond 0..0.08 m, negative effort)."""


class RenderUnavailable(RenderError):
    """No GL context can be made in this process (GL disabled, no display, or an earlier
    attempt failed); the depth camera then ray-casts and no video is rendered."""
