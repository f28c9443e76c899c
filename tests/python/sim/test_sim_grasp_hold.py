"""A closed grasp holds by friction alone: close on the object, lift 10 cm, hold 2 s.

Uses ground truth for the object pose (the only test allowed to) and a simple IK; the real
motion layer is not involved.
"""

from __future__ import annotations

import numpy as np
import pytest

from grasp_pipeline.sim.ground_truth import object_truth

LIFT_M = 0.10
HOLD_S = 2.0
MAX_SLIP_M = 0.005
STALL_SPEED_MPS = 0.005   # method.md §7
STALL_TIME_S = 0.5
CLOSE_TIMEOUT_S = 8.0
EFFORT_N = 40.0


def _close_until_stall(world) -> bool:
    world.set_gripper(0.0, EFFORT_N)
    t0, still = world.time_s, 0.0
    while world.time_s - t0 < CLOSE_TIMEOUT_S:
        world.step()
        moving = abs(world.finger_speed_mps) >= STALL_SPEED_MPS
        still = 0.0 if moving or world.time_s - t0 < 0.1 else still + world.timestep_s
        if still >= STALL_TIME_S:
            return True
    return False


def _object_in_tcp(world, name):
    return np.linalg.inv(world.tcp_pose()) @ object_truth(world, name).T_world_object


@pytest.mark.parametrize("name", ["blue_cube", "green_cylinder"])
def test_grasp_lift_and_hold(make_world, motion, name):
    world = make_world(camera=False)
    truth = object_truth(world, name)
    centre = truth.position_m
    R = truth.T_world_object[:3, :3]
    y_now = world.tcp_pose()[:3, 1]
    closing = max([R[:, 0], -R[:, 0], R[:, 1], -R[:, 1]], key=lambda v: float(v @ y_now))

    def tcp_at(dz):
        return motion.top_down(centre + [0.0, 0.0, dz], closing)

    q_pre = motion.ik_tcp(tcp_at(0.12), world.q)
    motion.move(world, q_pre, 2.0)
    qs = [q_pre]
    for k in range(1, 7):                      # straight descent to the grasp pose
        qs.append(motion.ik_tcp(tcp_at(0.12 * (1 - k / 6)), qs[-1]))
    world.run_until(world.follow_trajectory(np.linspace(0, 1.5, len(qs)), np.array(qs)) + 0.5)
    assert np.linalg.norm(world.tcp_pose()[:3, 3] - centre) < 0.002
    assert world.robot_contacts(include_objects=False) == []

    assert _close_until_stall(world), "fingers never stalled"
    width = truth.size_m[1] if name.endswith("cylinder") else truth.size_m[0]
    assert abs(world.finger_gap_m - width) < 0.002, "stalled away from the object's width"
    assert world.gripper_force_N == pytest.approx(EFFORT_N, rel=0.05)
    before = _object_in_tcp(world, name)
    z_before = object_truth(world, name).position_m[2]

    qs = [qs[-1]]
    for k in range(1, 6):
        qs.append(motion.ik_tcp(tcp_at(LIFT_M * k / 5), qs[-1]))
    world.run_until(world.follow_trajectory(np.linspace(0, 1.5, len(qs)), np.array(qs)))
    lifted = object_truth(world, name).position_m[2] - z_before
    world.run_until(world.time_s + HOLD_S)
    after = _object_in_tcp(world, name)
    slip = float(np.linalg.norm(after[:3, 3] - before[:3, 3]))

    assert lifted > LIFT_M - 0.005, f"object rose only {lifted * 1000:.1f} mm"
    assert object_truth(world, name).position_m[2] - z_before > LIFT_M - MAX_SLIP_M
    assert slip < MAX_SLIP_M, f"object slipped {slip * 1000:.2f} mm in the hand"
    print(f"{name}: lifted {lifted * 1000:.1f} mm, slip {slip * 1000:.2f} mm over lift + {HOLD_S} s")


def test_weak_grip_drops_the_object(make_world, motion):
    """The hold comes from friction: a grip too weak for the weight lets the cube slide out."""
    world = make_world(camera=False)
    truth = object_truth(world, "blue_cube")
    centre = truth.position_m
    closing = truth.T_world_object[:3, 0]
    q_pre = motion.ik_tcp(motion.top_down(centre + [0, 0, 0.1], closing), world.q)
    q_grasp = motion.ik_tcp(motion.top_down(centre, closing), q_pre)
    motion.move(world, q_pre, 1.5)
    motion.move(world, q_grasp, 1.0)
    world.set_gripper(0.0, 0.2)   # 0.2 N squeeze, mu 1.5: 0.6 N < 0.98 N weight
    world.run_until(world.time_s + 1.0)
    z0 = object_truth(world, "blue_cube").position_m[2]
    motion.move(world, q_pre, 1.0)
    assert object_truth(world, "blue_cube").position_m[2] - z0 < 0.01
