"""The arm's joint reference in the simulator: a timed trajectory sampled at the physics steps.

:class:`TrajectoryReference` is ``q(t)``, ``qd(t)`` on absolute simulated time — per segment a
cubic in the normalised time ``s`` (Hermite from the sample velocities, or linear without
them); before the first sample it holds ``q[0]``, after the last ``q[-1]`` (zero velocity) —
and the servo command derived from it, ``ctrl = q + (kv/kp) qd``.

It is read at every physics step (the command before the step, the reference again by the
motion monitor after it), so it is evaluated ahead, for a block of the coming step times at
once: the step times are the simulator's own (``time + timestep``, added up one step at a
time in double precision, as the physics advances its clock), and a time that is not one of
them is evaluated on its own. Both paths do the same floating-point operations in the same
order, so a sample is bit-identical whichever path gives it (the tests compare them).
"""

from __future__ import annotations

import numpy as np

#: Step times evaluated ahead at once (0.5 s at the 2 ms physics step).
BLOCK_STEPS = 256


class TrajectoryReference:
    """A joint reference ``q(t)``, ``qd(t)`` and its servo command ``q + kv_over_kp * qd``.

    Args:
        t_abs: (K,) strictly increasing absolute times [s].
        q: (K, J) joint positions; ``qd``: (K, J) velocities or None (piecewise linear).
        kv_over_kp: (J,) velocity-to-position gain ratio of the servos.
        step_s: the physics step [s]: the spacing of the step times evaluated ahead.

    Returned arrays are read-only views (shared with later calls); copy before changing them.
    """

    def __init__(self, t_abs: np.ndarray, q: np.ndarray, qd: np.ndarray | None,
                 kv_over_kp: np.ndarray, step_s: float):
        self.t = t_abs
        self.q = q
        self.h = np.diff(t_abs)
        self.coef = _segment_coefficients(q, qd, self.h)
        self._kv = np.asarray(kv_over_kp, dtype=float)
        self._step_s = float(step_s)
        zero = _frozen(np.zeros(q.shape[1]))
        first, last = _frozen(q[0].copy()), _frozen(q[-1].copy())
        self._first = (first, zero, _frozen(first + self._kv * zero))
        self._last = (last, zero, _frozen(last + self._kv * zero))
        self._t0, self._t_end = float(t_abs[0]), float(t_abs[-1])
        self._times: list[float] = []
        self._rows: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []
        self._k = 0

    @property
    def end_time_s(self) -> float:
        return self._t_end

    def sample(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        """``(q, qd)`` at time ``t``."""
        q, qd, _ = self._at(t)
        return q, qd

    def command(self, t: float) -> np.ndarray:
        """The servo command ``q(t) + kv_over_kp * qd(t)``."""
        return self._at(t)[2]

    # ------------------------------------------------------------------ internals
    def _at(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        if t < self._t0 or len(self.t) == 1:
            return self._first
        if t >= self._t_end:
            return self._last
        k, times = self._k, self._times
        if k < len(times) and times[k] == t:
            return self._rows[k]
        if k + 1 < len(times) and times[k + 1] == t:
            self._k = k + 1
            return self._rows[k + 1]
        return self._evaluate_ahead(t)

    def _evaluate_ahead(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Evaluate the step times ``t, t + step, t + 2 step, ...`` (up to the end, at most
        :data:`BLOCK_STEPS`) and serve ``t``."""
        times = [t]
        while len(times) < BLOCK_STEPS and times[-1] < self._t_end:
            times.append(times[-1] + self._step_s)
        T = np.array(times)
        q, qd = self._evaluate(T)
        ctrl = q + self._kv * qd
        for a in (q, qd, ctrl):
            a.flags.writeable = False
        self._times = times
        self._rows = list(zip(q, qd, ctrl))
        self._k = 0
        return self._rows[0]

    def _evaluate(self, T: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(q, qd) at the times ``T`` (B,), each row computed as a single sample would be."""
        tt = self.t
        inside = (T >= tt[0]) & (T < tt[-1])
        i = np.clip(np.searchsorted(tt, T, side="right") - 1, 0, len(self.h) - 1)
        h = self.h[i]
        s = ((T - tt[i]) / h)[:, None]
        a, b, c, d = (self.coef[i, j] for j in range(4))
        q = ((d * s + c) * s + b) * s + a
        qd = ((3.0 * d * s + 2.0 * c) * s + b) / h[:, None]
        if not inside.all():  # before the start / after the end: held, zero velocity
            before = T < tt[0]
            q[~inside] = np.where(before[~inside, None], self.q[0], self.q[-1])
            qd[~inside] = 0.0
        return q, qd


def _segment_coefficients(q: np.ndarray, qd: np.ndarray | None, h: np.ndarray) -> np.ndarray:
    """(K-1, 4, J) cubic coefficients ``a + b s + c s^2 + d s^3`` per segment."""
    if len(h) == 0:
        return np.zeros((0, 4, q.shape[1]))
    if qd is None:
        dq = np.diff(q, axis=0)
        zero = np.zeros_like(dq)
        return np.stack([q[:-1], dq, zero, zero], axis=1)
    m0 = qd[:-1] * h[:, None]
    m1 = qd[1:] * h[:, None]
    q0, q1 = q[:-1], q[1:]
    return np.stack([q0, m0, 3 * (q1 - q0) - 2 * m0 - m1, 2 * (q0 - q1) + m0 + m1], axis=1)


def _frozen(a: np.ndarray) -> np.ndarray:
    a.flags.writeable = False
    return a
