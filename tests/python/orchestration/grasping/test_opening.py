"""The gripper's usable opening: one definition from the robot's opening and one margin."""

import dataclasses

import pytest

from grasp_pipeline.orchestration.config import GraspConfig, GraspFitConfig
from grasp_pipeline.orchestration.grasping.opening import full_margin_width_m, max_grasp_width_m
from grasp_pipeline.robot.limits import GRIPPER_MAX_WIDTH_M


def test_the_usable_opening_is_the_hand_s_opening_less_the_least_spare():
    fit = GraspFitConfig()
    assert max_grasp_width_m(fit) == pytest.approx(0.072)
    wider = dataclasses.replace(fit, min_open_margin_m=0.004)
    assert max_grasp_width_m(wider) == pytest.approx(GRIPPER_MAX_WIDTH_M - 0.004)


def test_the_full_margin_width_leaves_the_whole_approach_margin():
    grasp = GraspConfig()
    assert full_margin_width_m(grasp) == pytest.approx(0.06)
    assert full_margin_width_m(grasp) + grasp.open_margin_m == pytest.approx(GRIPPER_MAX_WIDTH_M)
    assert full_margin_width_m(grasp) < max_grasp_width_m(GraspFitConfig())
