"""Time parameterisation of joint paths with TOPP-RA (PyPI ``toppra``).

The geometric path (waypoints) is densified to ``timing_waypoint_step_rad`` per joint,
fitted with a cubic spline over its cumulative joint-space length (dense knots keep the
spline within a small fraction of a degree of the polyline; the result is re-checked
for collisions by the planner anyway), then TOPP-RA computes the time-optimal speed
profile under the Panda's joint velocity and acceleration limits times
``velocity_scale`` / ``acceleration_scale``. The trajectory starts and ends at rest and
is sampled at ``control_rate_hz``.

TOPP-RA enforces the limits at its grid points; between them a sample may overshoot
slightly. Every sample is therefore checked, and if any exceeds a limit by more than
``timing_limit_tolerance`` the whole trajectory is slowed down uniformly (time scaled by
k: velocities / k, accelerations / k²) so that every sample complies.
"""

from __future__ import annotations

import logging
import time

import numpy as np

from .config import MotionConfig
from .exceptions import TimeParameterizationError
from .toppra_import import import_toppra
from .trajectory import JointPath, JointTrajectory

log = logging.getLogger(__name__)

_DUPLICATE_TOL_RAD = 1e-9


def densify(waypoints: np.ndarray, max_step_rad: float) -> np.ndarray:
    """Insert points on every segment so that no joint moves more than ``max_step_rad``."""
    out = [waypoints[0]]
    for a, b in zip(waypoints[:-1], waypoints[1:]):
        n = max(1, int(np.ceil(np.max(np.abs(b - a)) / max_step_rad)))
        s = np.arange(1, n + 1)[:, None] / n
        out.extend(a + (b - a) * s)
    return np.asarray(out)


class TrajectoryTimer:
    """TOPP-RA timing with scaled joint limits.

    ``qd_max`` / ``qdd_max``: the robot's (unscaled) limits, shape (7,); the config's
    ``velocity_scale`` / ``acceleration_scale`` are applied here.
    """

    def __init__(self, qd_max: np.ndarray, qdd_max: np.ndarray, config: MotionConfig) -> None:
        self.config = config
        self.qd_limit = np.asarray(qd_max, dtype=float) * config.velocity_scale
        self.qdd_limit = np.asarray(qdd_max, dtype=float) * config.acceleration_scale
        self.dt_s = 1.0 / config.control_rate_hz
        self._constraints_cache: tuple | None = None

    def time_path_stop_at_waypoints(self, path: JointPath | np.ndarray) -> JointTrajectory:
        """Time every segment separately (rest at each waypoint): the joints follow the
        polyline exactly. Slower to execute; the fallback when a smooth spline would leave
        the collision-checked polyline by too much near an obstacle."""
        jp = path if isinstance(path, JointPath) else None
        wp = np.asarray(path.waypoints if jp is not None else path, dtype=float)
        parts = [self.time_path(wp[k:k + 2]) for k in range(len(wp) - 1)] or [self.time_path(wp[:1])]
        t, q, qd, qdd, ms = [parts[0].t_s], [parts[0].q], [parts[0].qd], [parts[0].qdd], parts[0].timing_ms
        for p in parts[1:]:
            if p.num_samples < 2:
                continue
            t.append(t[-1][-1] + p.t_s[1:])
            q.append(p.q[1:])
            qd.append(p.qd[1:])
            qdd.append(p.qdd[1:])
            ms += p.timing_ms
        return JointTrajectory(np.concatenate(t), np.vstack(q), np.vstack(qd), np.vstack(qdd),
                               timing_ms=ms, path=jp)

    def time_path(self, path: JointPath | np.ndarray, waypoint_step_rad: float | None = None) -> JointTrajectory:
        """Time a path (JointPath or (M, 7) waypoints); raise TimeParameterizationError on failure.

        ``waypoint_step_rad``: densification step before the spline fit (default from the
        config); smaller keeps the spline closer to the polyline at corners."""
        toppra = import_toppra()
        algo = toppra.algorithm

        jp = path if isinstance(path, JointPath) else None
        wp = np.asarray(path.waypoints if jp is not None else path, dtype=float)
        if wp.ndim != 2 or wp.shape[1] != len(self.qd_limit) or len(wp) < 1:
            raise TimeParameterizationError(f"path must be (M, {len(self.qd_limit)}), got {wp.shape}")
        if not np.all(np.isfinite(wp)):
            raise TimeParameterizationError("path contains NaN/Inf joint values")
        t0 = time.perf_counter()
        keep = np.concatenate([[True], np.max(np.abs(np.diff(wp, axis=0)), axis=1) > _DUPLICATE_TOL_RAD])
        wp = wp[keep]
        if len(wp) == 1:
            tr = JointTrajectory.hold(wp[0])
            return JointTrajectory(tr.t_s, tr.q, tr.qd, tr.qdd,
                                   timing_ms=(time.perf_counter() - t0) * 1e3, path=jp)
        dense = densify(wp, waypoint_step_rad or self.config.timing_waypoint_step_rad)
        ss = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(dense, axis=0), axis=1))])
        if len(dense) == 2:
            # a straight line: a 3-knot spline keeps it exactly linear
            dense = np.vstack([dense[0], 0.5 * (dense[0] + dense[1]), dense[1]])
            ss = np.array([0.0, 0.5 * ss[-1], ss[-1]])
        geo = toppra.SplineInterpolator(ss, dense)
        n_grid = max(self.config.toppra_gridpoints, 2 * len(dense))
        grid = np.linspace(0.0, ss[-1], n_grid)
        instance = algo.TOPPRA(self._constraints(), geo, gridpoints=grid, parametrizer="ParametrizeConstAccel")
        traj = instance.compute_trajectory(0.0, 0.0)
        if traj is None:
            raise TimeParameterizationError(
                f"TOPP-RA found no feasible timing for a {len(wp)}-waypoint path "
                f"({ss[-1]:.3f} rad long) under the scaled limits")
        duration = float(traj.duration)
        # uniform slow-down if any sample exceeds a limit (TOPP-RA bounds hold at grid points only)
        k = 1.0
        for _ in range(3):
            t_s, q, qd, qdd = self._sample(traj, duration, k)
            ratio_v = np.max(np.abs(qd) / self.qd_limit)
            ratio_a = np.max(np.abs(qdd) / self.qdd_limit)
            if max(ratio_v, ratio_a) <= 1.0 + self.config.timing_limit_tolerance:
                break
            k *= max(ratio_v, np.sqrt(ratio_a), 1.0) * (1.0 + 1e-3)
            log.debug("TOPP-RA samples over the limits (v x%.4f, a x%.4f): slowing down by %.4f",
                      ratio_v, ratio_a, k)
        else:
            raise TimeParameterizationError(
                f"timed samples exceed the scaled limits (velocity x{ratio_v:.3f}, "
                f"acceleration x{ratio_a:.3f}) even after slowing down")
        q[0], q[-1] = wp[0], wp[-1]
        qd[0] = qd[-1] = 0.0
        ms = (time.perf_counter() - t0) * 1e3
        return JointTrajectory(t_s=t_s, q=q, qd=qd, qdd=qdd, timing_ms=ms, path=jp)

    def _constraints(self) -> list:
        """TOPP-RA's joint velocity and acceleration constraints of the scaled limits (made
        once per pair of limits: they hold no state of a path, and building them costs more
        than a short path's timing)."""
        constraint = import_toppra().constraint

        key = (self.qd_limit.tobytes(), self.qdd_limit.tobytes())
        cached = self._constraints_cache
        if cached is None or cached[0] != key:
            cached = (key, [
                constraint.JointVelocityConstraint(np.stack([-self.qd_limit, self.qd_limit], axis=1)),
                constraint.JointAccelerationConstraint(np.stack([-self.qdd_limit, self.qdd_limit], axis=1))])
            self._constraints_cache = cached
        return cached[1]

    def _sample(self, traj, duration: float, k: float):
        total = duration * k
        n = int(np.floor(total / self.dt_s + 1e-9))
        t_s = np.arange(n + 1) * self.dt_s
        if total - t_s[-1] > 1e-9:
            t_s = np.append(t_s, total)
        tau = np.minimum(t_s / k, duration)
        q, qd, qdd = _evaluate(traj, tau)
        return t_s, q, qd / k, qdd / (k * k)


def _evaluate(traj, tau: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Joint positions, velocities and accelerations of the TOPP-RA trajectory ``traj`` at the
    times ``tau``: ``traj(tau)``, ``traj(tau, 1)`` and ``traj(tau, 2)``.

    A constant-acceleration parametrisation (``ParametrizeConstAccel``) finds the path
    position, speed and acceleration of each time in a Python loop on every call: here that is
    done once for the three, with the very formulas of its ``__call__`` (the same values)."""
    eval_params, path = getattr(traj, "_eval_params", None), getattr(traj, "_path", None)
    if eval_params is None or path is None:
        return np.asarray(traj(tau)), np.asarray(traj(tau, 1)), np.asarray(traj(tau, 2))
    ss, vs, us = eval_params(tau)
    d1 = path(ss, 1)
    qd = np.multiply(d1, vs[:, np.newaxis])
    qdd = np.multiply(path(ss, 2), vs[:, np.newaxis] ** 2) + np.multiply(d1, us[:, np.newaxis])
    return np.asarray(path(ss)), np.asarray(qd), np.asarray(qdd)
