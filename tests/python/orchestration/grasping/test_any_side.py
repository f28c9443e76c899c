"""The any-side grasp source on synthetic scenes with known answers."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from grasp_pipeline.motion.config import load_motion_config
from grasp_pipeline.objects import shapes
from grasp_pipeline.orchestration.grasping.any_side import AnySideGraspSource
from grasp_pipeline.orchestration.grasping.grasp import GraspKind

from .seen_scenes import Scene, placed

ABOVE = (0.3, 0.0, 0.65)      # the robot's side, looking down at the table
SIDE = (0.75, -0.35, 0.3)     # a lower view from the far side


@pytest.fixture(scope="module")
def source():
    return AnySideGraspSource(motion=load_motion_config())


def test_a_box_wider_than_the_hand_leaning_on_another_is_grasped_with_a_tilted_approach(source):
    box = placed(shapes.box_parts(0.11, 0.095, 0.035), Rotation.from_euler("y", -35, degrees=True).as_matrix(),
                 (0.50, 0.0, 0.0))
    support = placed(shapes.box_parts(0.015, 0.06, 0.02), position=(0.47, 0.0, 0.0))
    scene = Scene({1: box, 2: support}, [ABOVE, SIDE])
    footprint = box.bounds[1][:2] - box.bounds[0][:2]
    assert np.all(footprint > 0.08)  # wider than the hand from above, both ways
    grasps = source.propose(scene.request(1))
    assert grasps, source.last_refusal
    best = grasps[0]
    assert best.kind is GraspKind.TILTED and best.tilt_deg >= 40.0
    thickness_axis = Rotation.from_euler("y", -35, degrees=True).as_matrix()[:, 2]
    assert abs(best.closing @ thickness_axis) > 0.9  # closes across the box's thickness
    assert 0.03 <= best.width_m <= 0.05


def test_a_mug_lying_on_its_side_is_grasped_across_its_body(source):
    lying = Rotation.from_euler("y", 90, degrees=True).as_matrix()
    mug = placed(shapes.mug_parts(0.033, 0.09), lying @ Rotation.from_euler("z", 90, degrees=True).as_matrix())
    scene = Scene({1: mug}, [ABOVE])
    grasps = source.propose(scene.request(1))
    assert grasps, source.last_refusal
    axis = np.array([1.0, 0.0, 0.0])  # the mug's axis lies along world x
    best = grasps[0]
    assert abs(best.closing @ axis) < 0.3
    assert 0.055 <= best.width_m <= 0.072


def test_a_bottle_lying_down_is_grasped_across(source):
    lying = Rotation.from_euler("x", 90, degrees=True).as_matrix()
    bottle = placed(shapes.bottle_parts(0.03, 0.2, 0.012, 0.04, 0.03), lying)
    scene = Scene({1: bottle}, [ABOVE])
    grasps = source.propose(scene.request(1))
    assert grasps, source.last_refusal
    best = grasps[0]
    assert abs(best.closing @ np.array([0.0, 1.0, 0.0])) < 0.3  # the bottle lies along y
    assert 0.05 <= best.width_m <= 0.066


def test_an_object_too_wide_in_every_direction_gets_no_grasp_and_a_reason(source):
    big = placed(shapes.box_parts(0.10, 0.10, 0.09))
    scene = Scene({1: big}, [ABOVE])
    assert source.propose(scene.request(1)) == []
    assert "too wide" in source.last_refusal


def test_a_cube_is_grasped_from_straight_above(source):
    cube = placed(shapes.box_parts(0.05, 0.05, 0.05))
    scene = Scene({1: cube}, [ABOVE])
    grasps = source.propose(scene.request(1))
    assert grasps and grasps[0].kind is GraspKind.TOP_DOWN
    assert abs(grasps[0].width_m - 0.05) < 0.006


def test_when_the_best_scored_grasps_all_meet_a_neighbour_the_next_ones_are_checked():
    # a box narrow across y between two taller walls 12 mm off its y faces: every grasp closing
    # across y (the narrowest, best scored) meets a wall; across x the fingers are free
    import dataclasses

    box = placed(shapes.box_parts(0.05, 0.045, 0.05))
    walls = {k: placed(shapes.box_parts(0.08, 0.02, 0.08), position=(0.5, s * 0.0445, 0.0))
             for k, s in ((2, 1.0), (3, -1.0))}
    scene = Scene({1: box, **walls}, [ABOVE])
    base = AnySideGraspSource(motion=load_motion_config())
    one = dataclasses.replace(base.config, preselect=1, preselect_batches=1)
    alone = AnySideGraspSource(config=one, motion=load_motion_config())
    assert alone.propose(scene.request(1)) == []
    assert "meets a neighbour" in alone.last_refusal
    more = AnySideGraspSource(config=dataclasses.replace(one, preselect_batches=400), motion=load_motion_config())
    grasps = more.propose(scene.request(1))
    assert grasps, more.last_refusal
    assert abs(grasps[0].closing @ np.array([1.0, 0.0, 0.0])) > 0.9  # across x, clear of the walls
