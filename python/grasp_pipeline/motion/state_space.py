"""OMPL wiring: the 7-D joint space, a batch motion validator, planner construction.

OMPL 2.0.1 from PyPI (nanobind API): states come from ``space.allocState()``, values are
``s[i]``; a plain Python callable is accepted as state validity checker (we pass the C++
checker's bound method); a Python subclass of ``ompl.base.MotionValidator`` replaces the
default discrete motion check so that one edge is one call into the C++ checker (instead of
one Python callback per interpolated state).
"""

from __future__ import annotations

import numpy as np

from .config import MotionConfig
from .validity import StateValidator

_OMPL_QUIET = False


def import_ompl():
    """Import ``ompl.base``, ``ompl.geometric``, ``ompl.util`` and silence OMPL's info logs."""
    global _OMPL_QUIET
    import ompl.base as ob
    import ompl.geometric as og
    import ompl.util as ou

    if not _OMPL_QUIET:
        ou.setLogLevel(ou.LOG_ERROR)
        _OMPL_QUIET = True
    return ob, og, ou


def state_to_array(s, n: int = 7) -> np.ndarray:
    return np.array([s[i] for i in range(n)])


def make_space(q_min: np.ndarray, q_max: np.ndarray):
    """RealVectorStateSpace with the joint limits as bounds."""
    ob, _, _ = import_ompl()
    space = ob.RealVectorStateSpace(len(q_min))
    bounds = ob.RealVectorBounds(len(q_min))
    for i, (lo, hi) in enumerate(zip(q_min, q_max)):
        bounds.setLow(i, float(lo))
        bounds.setHigh(i, float(hi))
    space.setBounds(bounds)
    return space


def make_state(space, q: np.ndarray):
    s = space.allocState()
    for i, v in enumerate(q):
        s[i] = float(v)
    return s


def make_motion_validator(si, validator: StateValidator, step_rad: float):
    """A MotionValidator whose ``checkMotion`` hands both OMPL states straight to the C++
    checker (``check_ompl_motion``: reads ``s[0:7]``, checks the edge's states at ≤
    ``step_rad`` per joint, coarse-to-fine, first invalid state ends it). The start state
    of an edge is valid by OMPL's contract and not re-checked."""
    ob, _, _ = import_ompl()
    check_motion = validator.core().check_ompl_motion

    class CoreMotionValidator(ob.MotionValidator):
        def checkMotion(self, s1, s2, *rest):  # noqa: N802 (OMPL's name)
            return check_motion(s1, s2, step_rad)

    return CoreMotionValidator(si)


def state_validity_checker(validator: StateValidator):
    """The OMPL state validity callable: the C++ checker's ``check_ompl_state`` itself (no
    Python frame per call)."""
    return validator.core().check_ompl_state


def make_planner(name: str, si, config: MotionConfig):
    """Construct the configured OMPL geometric planner."""
    _, og, _ = import_ompl()
    cls = getattr(og, name, None)
    if cls is None:
        raise ValueError(f"OMPL has no geometric planner {name!r}")
    planner = cls(si)
    if config.planner_range_rad > 0 and hasattr(planner, "setRange"):
        planner.setRange(config.planner_range_rad)
    return planner
