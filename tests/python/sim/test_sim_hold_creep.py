"""Holding is force-controlled: an object squeezed across slanted faces creeps between the
pads (its faces push it out along the approach) in MuJoCo's soft contacts, and the grip keeps
squeezing it; the simulated cell runs no-slip passes while the hand holds, and it stays put.

The yellow prism lies on a rectangular face (a roof); the pads close across its two faces
tilted 30 deg from vertical. Closing uses the product's routine (``close_until_stall``); with
``hold_by_force`` the fingers are then commanded shut at the closing effort, without it the
close command stays and the squeeze fades as the gap creeps towards that command. Ground
truth is read only to place the hand and to score.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from grasp_pipeline.objects.builtin import builtin_object
from grasp_pipeline.orchestration.config import GraspConfig
from grasp_pipeline.orchestration.execution.gripper_moves import close_until_stall, hold_lost
from grasp_pipeline.sim.ground_truth import object_truth
from grasp_pipeline.sim.scene_spec import ObjectSpec, SceneSpec
from grasp_pipeline.sim.scenes import reference_scene

LIFT_M = 0.10
HOLD_S = 6.0
PAD_CENTRE_ABOVE_TABLE_M = 0.026   # pads span 15..37 mm: contacts on the slanted faces


def _prism_scene(world_factory):
    ref = reference_scene()
    model = builtin_object("yellow_prism")
    ext = model.extents_m()
    spec = ObjectSpec("yellow_prism_0", "mesh", tuple(float(e) for e in ext),
                      (0.55, 0.0, ref.table_top_z_m + float(ext[2]) / 2 + 0.001),
                      rgba=tuple(model.rgba), mesh=model, category="prism")
    scene = SceneSpec("prism", (spec,), ref.table_top_z_m, ref.start_q)
    return world_factory(scene, camera=False)


def _run(world, task):
    try:
        while True:
            next(task)
            world.step()
    except StopIteration as done:
        return done.value


def _grasp_lift_hold(world, motion, config: GraspConfig):
    truth = object_truth(world, "yellow_prism_0")
    top_z = world.scene.table_top_z_m + PAD_CENTRE_ABOVE_TABLE_M
    centre = np.array([*truth.position_m[:2], top_z])
    across = truth.T_world_object[:3, 1]             # across the roof's slanted faces
    closing = across if across @ world.tcp_pose()[:3, 1] >= 0 else -across

    def tcp_at(dz):
        return motion.top_down(centre + [0.0, 0.0, dz], closing)

    q_pre = motion.ik_tcp(tcp_at(0.12), world.q)
    motion.move(world, q_pre, 2.0)
    motion.move(world, motion.ik_tcp(tcp_at(0.0), q_pre), 1.5)
    world.set_gripper(0.06, config.close_effort_N)
    world.run_until(world.time_s + 0.4)
    stall_gap = _run(world, close_until_stall(world, 0.03, config))
    z0 = object_truth(world, "yellow_prism_0").position_m[2]
    qs = [world.q.copy()]
    for k in range(1, 6):
        qs.append(motion.ik_tcp(tcp_at(LIFT_M * k / 5), qs[-1]))
    world.run_until(world.follow_trajectory(np.linspace(0, 1.5, len(qs)), np.array(qs)))
    lost_at = None
    t_end = world.time_s + HOLD_S
    while world.time_s < t_end:
        world.step()
        if lost_at is None and hold_lost(world, stall_gap, config):
            lost_at = world.time_s
    risen = object_truth(world, "yellow_prism_0").position_m[2] - z0
    return stall_gap, risen, lost_at


def _without_hold_passes(make_world):
    """Worlds without the no-slip passes while holding: the soft contacts' creep shows."""
    from grasp_pipeline.sim.config import load_sim_config

    sim = replace(load_sim_config(), noslip_hold_iterations=0, noslip_iterations=0)
    return lambda scene, camera: make_world(scene, sim_config=sim, camera=camera)


def test_a_prism_held_across_slanted_faces_stays_squeezed_while_it_creeps(make_world, motion):
    config = GraspConfig()
    assert config.hold_by_force
    world = _prism_scene(_without_hold_passes(make_world))
    stall_gap, risen, lost_at = _grasp_lift_hold(world, motion, config)
    print(f"stall {stall_gap * 1e3:.1f} mm, gap now {world.finger_gap_m * 1e3:.1f} mm, "
          f"force {world.gripper_force_N:.1f} N, risen {risen * 1e3:.0f} mm, lost at {lost_at}")
    assert lost_at is None
    assert risen > LIFT_M - 0.02
    assert world.gripper_force_N == pytest.approx(config.close_effort_N, rel=0.05)


def test_with_the_close_command_kept_the_squeeze_fades_as_the_gap_creeps(make_world, motion):
    """The failure the force-controlled hold removes: the same grasp with the close command
    kept loses its squeeze within the hold (measured: the gap crept to the command)."""
    config = replace(GraspConfig(), hold_by_force=False)
    world = _prism_scene(_without_hold_passes(make_world))
    stall_gap, risen, lost_at = _grasp_lift_hold(world, motion, config)
    print(f"stall {stall_gap * 1e3:.1f} mm, gap now {world.finger_gap_m * 1e3:.1f} mm, "
          f"force {world.gripper_force_N:.1f} N, risen {risen * 1e3:.0f} mm, lost at {lost_at}")
    assert lost_at is not None


def test_with_the_no_slip_passes_the_prism_does_not_creep(make_world, motion):
    """``sim.noslip_iterations`` removes the soft contacts' creep: the gap stays at the stall
    gap through the lift and the hold."""
    from grasp_pipeline.sim.config import load_sim_config

    sim = replace(load_sim_config(), noslip_iterations=5)
    world = _prism_scene(lambda scene, camera: make_world(scene, sim_config=sim, camera=camera))
    stall_gap, risen, lost_at = _grasp_lift_hold(world, motion, GraspConfig())
    assert lost_at is None and risen > LIFT_M - 0.002
    assert abs(world.finger_gap_m - stall_gap) < 0.001


def test_by_default_the_no_slip_passes_run_only_while_the_hand_holds(make_world, motion):
    """The simulated cell's default: no passes while the fingers are open (approaching), five
    while they are commanded shut on the prism — which then does not creep through the lift
    and the hold."""
    from grasp_pipeline.sim.config import load_sim_config

    sim = load_sim_config()
    assert sim.noslip_iterations == 0 and sim.noslip_hold_iterations > 0
    world = _prism_scene(make_world)
    world.step()
    assert world.model.opt.noslip_iterations == 0  # fingers open
    stall_gap, risen, lost_at = _grasp_lift_hold(world, motion, GraspConfig())
    assert world.model.opt.noslip_iterations == sim.noslip_hold_iterations
    assert lost_at is None and risen > LIFT_M - 0.002
    assert abs(world.finger_gap_m - stall_gap) < 0.001
    world.set_gripper(0.08)
    world.step()
    assert world.model.opt.noslip_iterations == 0  # released
