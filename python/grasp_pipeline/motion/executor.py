"""Executes timed joint trajectories on the simulated Panda and watches them.

``TrajectoryExecutor.execute(traj)`` hands the trajectory to ``SimWorld.follow_trajectory``
(with velocities: cubic Hermite reference) and steps the simulation, checking every
``monitor_every_steps`` physics steps:

* tracking error ``max_j |q_ref_j - q_j| > tracking_error_limit_rad`` → stop;
* an unexpected contact (the robot's :class:`~grasp_pipeline.robot.protocols.ContactMonitor`
  given the motion's :class:`~grasp_pipeline.robot.protocols.ContactAllowance` — e.g. the
  fingers may touch objects while approaching) → stop, when ``stop_on_contact``.

The robot is anything implementing the clock, arm and contact-monitor protocols
(``SimWorld`` in the simulator).

Stopping means holding the *current* joints (``world.hold()``): the arm is never left
moving. After the trajectory's end the executor waits until every joint is within
``settle_position_tol_rad`` of the final sample and slower than
``settle_velocity_tol_rad_s`` (timeout ``settle_timeout_s`` → error, holding). Errors are
:class:`ExecutionError` with ``reason`` in {"tracking", "contact", "settle", "input"}.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from operator import sub

import numpy as np

from .config import MotionConfig
from .exceptions import ExecutionError
from ..robot.protocols import ContactAllowance
from .trajectory import JointTrajectory

log = logging.getLogger(__name__)

_MONITOR_EVERY_STEPS = 1


@dataclass
class ExecutionReport:
    """What happened: durations (simulated), worst tracking error, contacts seen, settle state."""

    duration_s: float = 0.0
    settle_time_s: float = 0.0
    max_tracking_error_rad: float = 0.0
    final_error_rad: float = 0.0
    settled: bool = False
    contacts: list[str] = field(default_factory=list)


class TrajectoryExecutor:
    """Follows trajectories on a robot (clock + arm + contact monitor) with monitoring and a
    safe stop."""

    def __init__(self, world, config: MotionConfig) -> None:
        self.world = world
        self.config = config

    def _stop(self, reason: str, message: str) -> None:
        q_commanded = np.array(self.world.reference()[0], dtype=float)
        q_measured = np.array(self.world.q, dtype=float)
        self.world.hold()  # hold the current joints
        t = float(self.world.time_s)
        log.warning("execution stopped (%s) at t=%.3f s: %s", reason, t, message)
        raise ExecutionError(f"execution stopped: {message}; the arm holds its current position",
                             reason=reason, time_s=t, q_commanded=q_commanded, q_measured=q_measured)

    def execute(self, traj: JointTrajectory, allowance: ContactAllowance = ContactAllowance.NONE,
                wait_settled: bool = True, release_contacts: bool = False) -> ExecutionReport:
        """Run ``traj`` to completion (blocking in simulated time); see the module doc.

        ``allowance``: which contacts this motion expects (e.g. ``FINGERS`` on the object
        being grasped). ``release_contacts``: contacts present when the motion starts are
        tolerated (a recovery moving away from what stopped the arm); new ones still stop it."""
        steps = self.execute_steps(traj, allowance, wait_settled, release_contacts)
        while True:
            try:
                next(steps)
            except StopIteration as done:
                return done.value

    def execute_steps(self, traj: JointTrajectory, allowance: ContactAllowance = ContactAllowance.NONE,
                      wait_settled: bool = True, release_contacts: bool = False):
        """Generator form of :meth:`execute` for cooperative callers (the orchestrator's
        runtime): it steps the world itself and yields after every physics step, so other
        tasks (a scan's status, perception) can run in between; returns the report."""
        cfg = self.config
        w = self.world
        rep = ExecutionReport()
        if traj.num_samples == 0 or not np.all(np.isfinite(traj.q)):
            raise ExecutionError("trajectory is empty or contains NaN", reason="input")
        start_err = float(np.max(np.abs(traj.q[0] - w.q)))
        if start_err > cfg.tracking_error_limit_rad:
            w.hold()
            raise ExecutionError(
                f"trajectory starts {start_err:.3f} rad away from the current joints "
                f"(limit {cfg.tracking_error_limit_rad} rad); not executed", reason="input")
        tolerated = set(w.unexpected_contacts(allowance)) if release_contacts else set()
        if tolerated:
            log.info("moving away from contacts %s", sorted(tolerated))
        t_start = float(w.time_s)
        t_end = w.follow_trajectory(traj.t_s, traj.q, traj.qd)
        t_stop = t_end - 0.5 * w.timestep_s
        try:
            while w.time_s < t_stop:
                w.step(_MONITOR_EVERY_STEPS)
                self._monitor(rep, allowance, tolerated)
                yield
            rep.duration_s = float(w.time_s - t_start)
            if wait_settled:
                q_final = traj.q[-1]
                t_limit = w.time_s + cfg.settle_timeout_s
                while True:
                    err = float(np.max(np.abs(w.q - q_final)))
                    if err <= cfg.settle_position_tol_rad and \
                            float(np.max(np.abs(w.qd))) <= cfg.settle_velocity_tol_rad_s:
                        rep.settled = True
                        break
                    if w.time_s >= t_limit:
                        j = int(np.argmax(np.abs(w.q - q_final)))
                        self._stop("settle", f"the arm did not settle within {cfg.settle_timeout_s} s "
                                             f"(error {err:.4f} rad at joint {j + 1}, "
                                             f"speed {np.max(np.abs(w.qd)):.4f} rad/s)")
                    w.step(_MONITOR_EVERY_STEPS)
                    self._monitor(rep, allowance, tolerated)
                    yield
                rep.settle_time_s = float(w.time_s - t_start - rep.duration_s)
            rep.final_error_rad = float(np.max(np.abs(w.q - traj.q[-1])))
        except ExecutionError:
            raise
        except BaseException:
            w.hold()
            raise
        return rep

    def _monitor(self, rep: ExecutionReport, allowance: ContactAllowance, tolerated: set) -> None:
        cfg = self.config
        w = self.world
        q_ref, _ = w.reference()
        err = max_abs_diff(q_ref.tolist(), w.q.tolist())
        rep.max_tracking_error_rad = max(rep.max_tracking_error_rad, err)
        if err > cfg.tracking_error_limit_rad:
            self._stop("tracking", f"tracking error {err:.4f} rad exceeds {cfg.tracking_error_limit_rad} rad")
        bad = [c for c in w.unexpected_contacts(allowance) if c not in tolerated]
        if bad:
            rep.contacts.extend(bad)
            if cfg.stop_on_contact:
                self._stop("contact", f"unexpected robot contact {sorted(set(bad))}")


def max_abs_diff(a: list, b: list) -> float:
    """``max_j |a_j - b_j|`` of two lists of finite floats: the same value as numpy's
    ``np.max(np.abs(a - b))`` (subtraction and ``abs`` round alike, the maximum is exact), at
    a fraction of its cost on the seven joints (read at every physics step)."""
    return max(map(abs, map(sub, a, b)))
