"""SimWorld: holding still, trajectory tracking, gripper, readouts, contacts, validation."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from grasp_pipeline.robot import description as rm
from grasp_pipeline.sim.config import load_sim_config
from grasp_pipeline.sim.exceptions import GripperError, TrajectoryError
from grasp_pipeline.robot.protocols import ContactAllowance
from grasp_pipeline.sim.ground_truth import object_truths
from grasp_pipeline.sim.object_geoms import geom_object
from grasp_pipeline.exceptions import ConfigError


def test_starts_at_ready_pose_and_holds_still(make_world):
    world = make_world(camera=False)
    assert world.timestep_s == 0.002
    np.testing.assert_allclose(world.q, rm.READY_Q)
    start = [o.position_m for o in object_truths(world)]
    world.run_until(1.0)
    assert world.time_s == pytest.approx(1.0)
    assert np.abs(world.q - rm.READY_Q).max() < 1e-4
    assert np.abs(world.qd).max() < 1e-3
    assert world.finger_gap_m == pytest.approx(rm.GRIPPER_MAX_WIDTH_M, abs=1e-4)
    assert world.robot_contacts() == []
    for p0, o in zip(start, object_truths(world)):
        assert np.linalg.norm(o.position_m - p0) < 0.001, f"{o.name} moved at rest"
        assert o.position_m[2] - 0.5 * o.size_m[2] == pytest.approx(0.200, abs=0.001)


def test_follows_a_timed_trajectory_tightly(make_world, motion):
    world = make_world(camera=False)
    q_goal = rm.READY_Q + np.array([0.5, 0.3, -0.3, 0.4, 0.5, -0.4, 0.6])
    t, q, qd = motion.minjerk(world.q, q_goal, 2.0, n=60)
    end = world.follow_trajectory(t, q, qd)
    assert end == pytest.approx(2.0)
    worst = 0.0
    while not world.trajectory_done():
        world.step()
        q_ref, _ = world.reference()
        worst = max(worst, float(np.abs(world.q - q_ref).max()))
    world.run_until(end + 0.3)
    assert worst < 0.01, f"tracking error {worst:.4f} rad"
    assert np.abs(world.q - q_goal).max() < 1e-3


def test_linear_trajectory_without_velocities(make_world):
    world = make_world(camera=False)
    q1 = rm.READY_Q + 0.1
    world.follow_trajectory([0.0, 1.0], np.vstack([rm.READY_Q, q1]))
    world.run_until(0.5)
    q_ref, qd_ref = world.reference()
    np.testing.assert_allclose(q_ref, rm.READY_Q + 0.05, atol=1e-9)
    np.testing.assert_allclose(qd_ref, 0.1, atol=1e-9)
    world.run_until(1.5)
    assert np.abs(world.q - q1).max() < 1e-3


@pytest.mark.parametrize("t, q", [
    ([0.0, 1.0], np.zeros((2, 6))),                                  # wrong width
    ([0.0, 0.0], np.vstack([rm.READY_Q, rm.READY_Q])),               # times not increasing
    ([0.0, 1.0], np.vstack([rm.READY_Q, rm.PANDA_Q_MAX + 0.1])),     # beyond limits
    ([0.0, np.nan], np.vstack([rm.READY_Q, rm.READY_Q])),            # NaN
])
def test_bad_trajectories_are_refused(make_world, t, q):
    with pytest.raises(TrajectoryError):
        make_world(camera=False).follow_trajectory(t, q)


def test_gripper_closes_opens_and_fingers_mirror(make_world):
    world = make_world(camera=False)
    world.set_gripper(0.0, 20.0)
    world.run_until(lambda w: w.finger_speed_mps < -0.02, max_duration_s=0.5)
    assert world.finger_speed_mps < 0        # closing is negative
    world.run_until(world.time_s + 1.5)
    assert world.finger_gap_m < 0.001
    q1, q2 = (world.data.qpos[world.model.joint(n).qposadr[0]] for n in rm.FINGER_JOINT_NAMES)
    assert abs(q1 - q2) < 1e-4
    world.set_gripper(0.05)
    world.run_until(world.time_s + 1.0)
    assert world.finger_gap_m == pytest.approx(0.05, abs=0.0005)
    assert abs(world.finger_speed_mps) < 0.001
    with pytest.raises(GripperError):
        world.set_gripper(0.09)
    with pytest.raises(GripperError):
        world.set_gripper(0.04, effort_N=500.0)


def test_run_until_predicate_times_out(make_world):
    world = make_world(camera=False)
    assert world.run_until(lambda w: False, max_duration_s=0.1) is False
    assert world.time_s == pytest.approx(0.1)


def test_robot_contacts_name_robot_and_environment_geoms(make_world, motion):
    world = make_world(camera=False)
    # push the closed fingertips 1 cm into the table, away from the objects
    world.set_gripper(0.0)
    target = motion.top_down(np.array([0.40, 0.20, 0.200 + 0.011 - 0.01]), world.tcp_pose()[:3, 1])
    q = motion.ik_tcp(target, world.q)
    motion.move(world, q, 2.0)
    contacts = world.robot_contacts(include_objects=False)
    assert contacts, "expected fingertip-table contacts"
    robot, other = zip(*contacts)
    assert set(other) == {"table_top"}
    assert all("finger" in r for r in robot)


def test_sim_config_validation():
    with pytest.raises(ConfigError):
        load_sim_config(overrides={"timestep_s": 0.01})
    with pytest.raises(ConfigError):
        load_sim_config(overrides={"region_x_m": [0.6, 0.4]})


def _contacts_one_by_one(world, include_objects: bool = True) -> list[tuple[str, str]]:
    """Robot / non-robot contacts the plain way: every contact of the data, in order."""
    out = []
    for c in world.data.contact[:world.data.ncon]:
        g1, g2 = int(c.geom1), int(c.geom2)
        r1, r2 = world.is_robot_geom(g1), world.is_robot_geom(g2)
        if r1 == r2:
            continue
        rg, og = (g1, g2) if r1 else (g2, g1)
        if include_objects or not world.geom_name(og).startswith("obj_"):
            out.append((world.geom_name(rg), world.geom_name(og)))
    return out


def _unexpected_one_by_one(world, allowance) -> list[str]:
    """The contact monitor's rule on the plain list: fingers on objects (FINGERS), anything on
    an object a finger touches (HELD_OBJECT), nothing (NONE) is expected."""
    contacts = _contacts_one_by_one(world)
    fingers_on = [(r, o) for r, o in contacts if "finger" in r and o.startswith("obj_")]
    if allowance is ContactAllowance.FINGERS:
        return [f"{r}-{o}" for r, o in contacts if (r, o) not in fingers_on]
    if allowance is ContactAllowance.HELD_OBJECT:
        held = {geom_object(o) for _, o in fingers_on}
        return [f"{r}-{o}" for r, o in contacts if geom_object(o) not in held]
    return [f"{r}-{o}" for r, o in contacts]


def test_robot_contacts_match_a_contact_by_contact_check(make_world, motion):
    """At every step of two descents with closed fingers — onto an object, then into the table
    away from the objects — the same pairs in the same order as a plain loop (steps without
    contact, with fingers on the object, with fingertips on the table), and the same
    unexpected contacts for every allowance (asked forward and backward by turns, so each
    step's first question is the previous step's last: an answer kept from an earlier step
    must follow the contacts)."""
    world = make_world(camera=False)
    world.set_gripper(0.0)
    obj = object_truths(world)[0]
    kinds = set()
    allowances = list(ContactAllowance)
    for xy, z_low in ((obj.position_m[:2], obj.position_m[2]), ((0.40, 0.20), 0.200 - 0.005)):
        above = motion.top_down(np.array([xy[0], xy[1], 0.32]), world.tcp_pose()[:3, 1])
        low = above.copy()
        low[2, 3] = z_low
        for T, duration_s in ((above, 1.0), (low, 0.8)):
            end = world.follow_trajectory(*motion.minjerk(world.reference()[0].copy(),
                                                          motion.ik_tcp(T, world.q), duration_s)[:2])
            while world.time_s < end + 0.1:
                world.step()
                for include in (True, False):
                    got = world.robot_contacts(include_objects=include)
                    assert got == _contacts_one_by_one(world, include), world.time_s
                for allowance in allowances:
                    assert world.unexpected_contacts(allowance) == _unexpected_one_by_one(world, allowance)
                allowances.reverse()
                kinds.update(other.split("_")[0] for _, other in world.robot_contacts())
    assert {"obj", "table"} <= kinds, f"the descents did not touch an object and the table: {kinds}"


def test_the_no_slip_passes_come_from_the_sim_config(make_world):
    cfg = replace(load_sim_config(), noslip_iterations=7)
    assert make_world(sim_config=cfg, camera=False).model.opt.noslip_iterations == 7
