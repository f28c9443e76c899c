"""TrajectoryReference: samples evaluated ahead for the step times are bit-identical to single
evaluations (the Hermite / linear formula written out here), hold before the start and after
the end, and stepping a world reuses the evaluated block."""

from __future__ import annotations

import numpy as np
import pytest

from grasp_pipeline.robot import description as rm
from grasp_pipeline.sim import joint_reference
from grasp_pipeline.sim.joint_reference import BLOCK_STEPS, TrajectoryReference

STEP_S = 0.002
KV = np.array([0.05, 0.04, 0.05, 0.03, 0.02, 0.02, 0.01])


def _single(t_abs, q, qd, t):
    """One sample the plain way: find the segment, evaluate its cubic in s = (t - t_i) / h."""
    if t < t_abs[0] or len(t_abs) == 1:
        return q[0], np.zeros(q.shape[1])
    if t >= t_abs[-1]:
        return q[-1], np.zeros(q.shape[1])
    i = int(np.searchsorted(t_abs, t, side="right")) - 1
    h = t_abs[i + 1] - t_abs[i]
    s = (t - t_abs[i]) / h
    if qd is None:
        return q[i] + (q[i + 1] - q[i]) * s, np.zeros(q.shape[1]) + (q[i + 1] - q[i]) / h
    m0, m1 = qd[i] * h, qd[i + 1] * h
    a, b = q[i], m0
    c = 3 * (q[i + 1] - q[i]) - 2 * m0 - m1
    d = 2 * (q[i] - q[i + 1]) + m0 + m1
    return ((d * s + c) * s + b) * s + a, ((3.0 * d * s + 2.0 * c) * s + b) / h


def _trajectory(rng, with_velocities: bool, t0: float = 0.37):
    t = t0 + np.cumsum(rng.uniform(0.004, 0.05, size=40))
    q = rm.READY_Q + rng.normal(scale=0.2, size=(40, 7))
    qd = rng.normal(scale=0.5, size=(40, 7)) if with_velocities else None
    return t, q, qd


@pytest.mark.parametrize("with_velocities", [True, False])
def test_step_times_and_single_times_give_the_plain_formula_bit_for_bit(with_velocities):
    rng = np.random.default_rng(3)
    t, q, qd = _trajectory(rng, with_velocities)
    ref = TrajectoryReference(t, q, qd, KV, STEP_S)
    now = 0.31  # before the start, then stepping the way the physics clock advances, past the end
    times = []
    while now < t[-1] + 0.02:
        times.append(now)
        now += STEP_S
    times += list(rng.uniform(t[0] - 0.1, t[-1] + 0.1, size=50))  # and arbitrary times
    for tk in times:
        q_ref, qd_ref = ref.sample(tk)
        q_exp, qd_exp = _single(t, q, qd, tk)
        assert np.array_equal(q_ref, q_exp), tk
        assert np.array_equal(qd_ref, qd_exp), tk
        assert np.array_equal(ref.command(tk), q_ref + KV * qd_ref), tk


def test_linear_segments_without_velocities():
    ref = TrajectoryReference(np.array([1.0, 2.0]), np.array([np.zeros(7), np.ones(7)]), None, KV, STEP_S)
    q, qd = ref.sample(1.5)
    np.testing.assert_allclose(q, 0.5, atol=1e-12)
    np.testing.assert_allclose(qd, 1.0, atol=1e-12)
    assert np.array_equal(ref.sample(0.5)[0], np.zeros(7)) and np.array_equal(ref.sample(0.5)[1], np.zeros(7))
    assert np.array_equal(ref.sample(2.5)[0], np.ones(7)) and np.array_equal(ref.sample(2.5)[1], np.zeros(7))


def test_a_hold_is_one_sample_at_any_time():
    q = rm.READY_Q.copy()
    ref = TrajectoryReference(np.array([4.0]), q[None, :], None, KV, STEP_S)
    for t in (0.0, 4.0, 9.0):
        q_ref, qd_ref = ref.sample(t)
        assert np.array_equal(q_ref, q) and not qd_ref.any()
        assert np.array_equal(ref.command(t), q + KV * 0.0)


def test_returned_arrays_are_read_only():
    rng = np.random.default_rng(0)
    t, q, qd = _trajectory(rng, True)
    ref = TrajectoryReference(t, q, qd, KV, STEP_S)
    for tk in (t[0] - 1.0, t[3] + 0.001, t[-1] + 1.0):
        q_ref, qd_ref = ref.sample(tk)
        with pytest.raises(ValueError):
            q_ref[0] = 1.0
        with pytest.raises(ValueError):
            ref.command(tk)[0] = 1.0


def test_stepping_a_world_reuses_the_block_evaluated_ahead(make_world, monkeypatch, motion):
    """The physics clock advances exactly as the block's step times do: a 2 s trajectory
    (1000 steps, command before and monitor after each) needs few block evaluations."""
    calls = []
    original = joint_reference.TrajectoryReference._evaluate_ahead

    def counting(self, t):
        calls.append(t)
        return original(self, t)

    monkeypatch.setattr(joint_reference.TrajectoryReference, "_evaluate_ahead", counting)
    world = make_world(camera=False)
    t, q, qd = motion.minjerk(world.q, rm.READY_Q + 0.2, 2.0, n=60)
    end = world.follow_trajectory(t, q, qd)
    while not world.trajectory_done():
        world.step()
        world.reference()  # the motion monitor's read after the step
    assert world.time_s >= end
    assert len(calls) <= 1000 // BLOCK_STEPS + 1, f"{len(calls)} block evaluations for 1000 steps"
