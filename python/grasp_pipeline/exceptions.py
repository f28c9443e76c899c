"""Exception hierarchy shared by every part of grasp_pipeline.

Each package raises a specific subclass so callers can tell *what* failed; every
message says what happened and what to do about it.
"""


class GraspPipelineError(Exception):
    """Base class of every error raised by grasp_pipeline."""


class ConfigError(GraspPipelineError, ValueError):
    """A configuration file or override is malformed, unknown or out of range."""


class InputError(GraspPipelineError, ValueError):
    """User-supplied data (a point cloud, a pose, a file) cannot be used as given."""


class RobotAdapterError(GraspPipelineError, ValueError):
    """A robot adapter breaks the contract of the robot protocols (``robot/protocols.py``):
    a member is missing or what it delivers cannot be used (docs/real_robot.md)."""


class CameraFrameError(RobotAdapterError):
    """A camera frame breaks the frame contract (``robot/frame_contract.py``): depth not in
    metres, intrinsics or camera pose missing or malformed, images that disagree in shape."""
