"""OMPL wiring: the 7-D joint space, a batch motion validator, planner construction.

OMPL 2.0.1 from PyPI (nanobind API): states come from ``space.allocState()``, values are
``s[i]``; a plain Python callable is accepted as state validity checker; a Python subclass
of ``ompl.base.MotionValidator`` replaces the default discrete motion check so that the
states of one edge are checked in one vectorised batch (a large speed-up over one Python
callback per state).
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
    """A MotionValidator that checks an edge's interpolated states (≤ ``step_rad`` per joint)
    in one batch. The start state of an edge is valid by OMPL's contract and not re-checked."""
    ob, _, _ = import_ompl()

    class BatchMotionValidator(ob.MotionValidator):
        def __init__(self, si_):
            super().__init__(si_)
            self.checks = 0

        def checkMotion(self, s1, s2, *rest):  # noqa: N802 (OMPL's name)
            self.checks += 1
            return validator.check_segment(state_to_array(s1), state_to_array(s2), step_rad)

    return BatchMotionValidator(si)


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
