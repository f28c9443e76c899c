"""Executing trajectories in the simulator: settling, safe stops (tracking error, contact)."""

import dataclasses

import numpy as np
import pytest

from grasp_pipeline.motion.exceptions import ExecutionError
from grasp_pipeline.motion.executor import TrajectoryExecutor, max_abs_diff
from grasp_pipeline.robot import description as rm
from grasp_pipeline.sim.world import SimWorld


@pytest.fixture()
def world():
    w = SimWorld(camera=False)
    yield w
    w.close()


def _assert_holding(w):
    q0 = w.q.copy()
    w.step(250)
    assert w.trajectory_done()
    assert np.max(np.abs(w.q - q0)) < 0.01
    assert np.max(np.abs(w.qd)) < 0.05


def test_execute_and_settle(planner, world):
    planner.set_scene(np.zeros((0, 3)))
    traj = planner.plan_to_joints(world.q, rm.NEUTRAL_Q)
    rep = TrajectoryExecutor(world, planner.config).execute(traj)
    assert rep.settled and not rep.contacts
    assert rep.final_error_rad <= planner.config.settle_position_tol_rad
    assert rep.max_tracking_error_rad < planner.config.tracking_error_limit_rad
    assert rep.duration_s == pytest.approx(traj.duration_s, abs=0.01)


def test_tracking_error_stops_and_holds(planner, world):
    planner.set_scene(np.zeros((0, 3)))
    traj = planner.plan_to_joints(world.q, rm.NEUTRAL_Q)
    strict = dataclasses.replace(planner.config, tracking_error_limit_rad=1e-5)
    with pytest.raises(ExecutionError, match="tracking error") as ei:
        TrajectoryExecutor(world, strict).execute(traj)
    assert ei.value.reason == "tracking"
    # the joints commanded and measured at the stop come with it (the arm's offset from its command)
    err = np.max(np.abs(ei.value.q_commanded - ei.value.q_measured))
    assert strict.tracking_error_limit_rad < err < 0.05
    _assert_holding(world)


def test_unexpected_contact_stops_and_holds(planner, world):
    """The planner is told the space is free (empty cloud); the real table is hit."""
    planner.set_scene(np.zeros((0, 3)))
    T = np.eye(4)
    T[:3, :3] = np.diag([1.0, -1.0, -1.0])
    T[:3, 3] = (0.62, 0.25, 0.12)  # below the table top (z = 0.2 m)
    traj = planner.plan_to_pose(world.q, T)
    with pytest.raises(ExecutionError, match="contact") as ei:
        TrajectoryExecutor(world, planner.config).execute(traj)
    assert ei.value.reason == "contact"
    _assert_holding(world)


def test_trajectory_far_from_current_state_refused(planner, world):
    planner.set_scene(np.zeros((0, 3)))
    traj = planner.plan_to_joints(rm.NEUTRAL_Q, rm.READY_Q)
    with pytest.raises(ExecutionError, match="away from the current joints"):
        TrajectoryExecutor(world, planner.config).execute(traj)


def test_max_abs_diff_is_numpys_value_bit_for_bit():
    rng = np.random.default_rng(7)
    for _ in range(200):
        a, b = rng.normal(scale=rng.choice([1e-6, 1e-3, 1.0, 3.0]), size=(2, 7))
        assert max_abs_diff(a.tolist(), b.tolist()) == float(np.max(np.abs(a - b)))
    assert max_abs_diff([0.0, -2.5], [0.0, 0.5]) == 3.0
