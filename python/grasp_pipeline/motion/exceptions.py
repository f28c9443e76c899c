"""Errors raised by the motion layer (IK, planning, timing, execution).

Every class derives from :class:`grasp_pipeline.exceptions.GraspPipelineError`, so a
caller can catch the whole family, or one specific failure. Messages say what was
asked, what went wrong and (where it applies) by how much.
"""

from __future__ import annotations

from typing import Optional

import numpy as np

from ..exceptions import GraspPipelineError, InputError


class MotionError(GraspPipelineError):
    """Base class of every motion-layer failure."""


class InvalidPoseError(MotionError, InputError):
    """A pose or joint vector given to the motion layer is malformed (NaN, wrong shape, not a rotation)."""


class UnreachablePoseError(MotionError):
    """No inverse-kinematics solution within the joint limits reaches the pose.

    Attributes ``position_residual_m`` and ``orientation_residual_rad`` tell how far the
    best attempt stayed from the target (``inf`` if no candidate was found at all).
    """

    def __init__(self, message: str, position_residual_m: float = float("inf"),
                 orientation_residual_rad: float = float("inf")) -> None:
        super().__init__(message)
        self.position_residual_m = position_residual_m
        self.orientation_residual_rad = orientation_residual_rad


class StartInCollisionError(MotionError):
    """The start joint state violates a limit or collides (self / environment / object box)."""


class GoalInCollisionError(MotionError):
    """The goal joint state violates a limit or collides (self / environment / object box)."""


class PlanningFailedError(MotionError):
    """The planner found no collision-free path within the time and attempt budget."""


class CartesianPathError(MotionError):
    """A straight-line Cartesian segment cannot be followed (IK gap, joint jump or collision)."""


class StartStateInvalidError(CartesianPathError):
    """A straight-line segment starts inside a clearance (e.g. a finger closed next to a
    neighbour): the line is not planned; moving straight away may still be possible."""


class TimeParameterizationError(MotionError):
    """TOPP-RA could not time the path within the joint velocity / acceleration limits."""


class EnvironmentCloudError(MotionError, InputError):
    """The environment point cloud cannot be used (wrong shape, over the size limit)."""


class ExecutionError(MotionError):
    """Following a trajectory was stopped (tracking error, contact, no settling); the arm holds still."""

    def __init__(self, message: str, reason: str = "", time_s: float = float("nan"),
                 q_commanded: Optional[np.ndarray] = None, q_measured: Optional[np.ndarray] = None) -> None:
        super().__init__(message)
        self.reason = reason
        self.time_s = time_s
        #: the joints commanded and measured when the arm was stopped (None: not known)
        self.q_commanded = q_commanded
        self.q_measured = q_measured
