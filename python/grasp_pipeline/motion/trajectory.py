"""Joint-space results of the motion layer: geometric paths and timed trajectories."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class JointPath:
    """A collision-checked geometric path (no timing).

    ``waypoints`` (M, 7) rad, start first. ``planning_ms`` is the wall time of the
    query, ``cpu_ms`` the CPU time of the planning thread during it (robust to load);
    ``method`` is ``"direct"`` (straight joint-space line), ``"cartesian"`` or
    the OMPL planner's name; ``attempts`` counts planner runs (0 for a direct line).
    """

    waypoints: np.ndarray
    planning_ms: float = 0.0
    method: str = "direct"
    attempts: int = 0
    checked_states: int = 0
    cpu_ms: float = 0.0

    @property
    def start(self) -> np.ndarray:
        return self.waypoints[0]

    @property
    def goal(self) -> np.ndarray:
        return self.waypoints[-1]

    def length_rad(self) -> float:
        """Joint-space L2 length."""
        return float(np.sum(np.linalg.norm(np.diff(self.waypoints, axis=0), axis=1)))


@dataclass(frozen=True)
class JointTrajectory:
    """A timed joint trajectory sampled at the control rate.

    ``t_s`` (K,) seconds from 0, ``q`` (K, 7) rad, ``qd`` (K, 7) rad/s, ``qdd`` (K, 7) rad/s².
    ``timing_ms`` is the TOPP-RA wall time; ``path`` the geometric path it was timed from.
    """

    t_s: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    timing_ms: float = 0.0
    path: JointPath | None = field(default=None, compare=False)

    @property
    def duration_s(self) -> float:
        return float(self.t_s[-1]) if len(self.t_s) else 0.0

    @property
    def num_samples(self) -> int:
        return int(len(self.t_s))

    def sample(self, time_s: float) -> np.ndarray:
        """Joint position at ``time_s`` (linear between samples, clamped to the ends)."""
        return np.array([np.interp(time_s, self.t_s, self.q[:, j]) for j in range(self.q.shape[1])])

    @staticmethod
    def hold(q: np.ndarray) -> "JointTrajectory":
        """A one-sample trajectory that keeps ``q``."""
        q = np.asarray(q, dtype=float).reshape(1, -1)
        z = np.zeros_like(q)
        return JointTrajectory(t_s=np.zeros(1), q=q, qd=z, qdd=z.copy())
