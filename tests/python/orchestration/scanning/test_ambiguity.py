"""Which segments the scan looks at again from closer above
(orchestration/scanning/ambiguity.py)."""

import numpy as np
import pytest

from grasp_pipeline.exceptions import ConfigError
from grasp_pipeline.orchestration.scanning.ambiguity import ambiguity, outline_solidity
from grasp_pipeline.orchestration.config import ScanConfig

from ..clouds import block, track_of

CFG = ScanConfig(closer_look_rules=("wide", "non_convex"))
MAX_WIDTH_M = 0.072  # the gripper's 80 mm opening less the fitted grasps' 8 mm spare


def _disc(radius_m, step_m=0.002):
    g = np.arange(-radius_m, radius_m + 1e-9, step_m)
    xx, yy = np.meshgrid(g, g)
    keep = np.hypot(xx, yy) <= radius_m
    return np.column_stack([0.5 + xx[keep], yy[keep], np.full(keep.sum(), 0.07)])


def test_a_filled_rectangle_is_convex_and_an_l_is_not():
    rect = block(0.50, 0.55, 0.0, 0.08, 0.0, 0.04)
    ell = np.vstack([block(0.50, 0.59, 0.0, 0.03, 0.0, 0.04), block(0.50, 0.53, 0.0, 0.09, 0.0, 0.04)])
    assert outline_solidity(rect[:, :2], CFG.closer_look_cell_m) == pytest.approx(1.0, abs=0.02)
    assert outline_solidity(ell[:, :2], CFG.closer_look_cell_m) < 0.8


def test_a_cylinder_seen_from_above_is_not_ambiguous():
    top = _disc(0.034)
    assert outline_solidity(top[:, :2], CFG.closer_look_cell_m) > CFG.closer_look_min_solidity
    assert ambiguity(track_of(3, top), top, MAX_WIDTH_M, CFG) is None


def test_two_cubes_meeting_at_a_corner_are_non_convex():
    pair = np.vstack([block(0.50, 0.53, 0.0, 0.03, 0.0, 0.04), block(0.53, 0.56, 0.03, 0.06, 0.0, 0.04)])
    why = ambiguity(track_of(1, pair), pair, MAX_WIDTH_M, CFG)
    assert why is not None and why.startswith("non-convex: outline fills")


def test_a_footprint_wider_than_the_gripper_everywhere_is_ambiguous_by_its_box_alone():
    wide = block(0.50, 0.581, 0.0, 0.075, 0.0, 0.04)
    why = ambiguity(track_of(2, wide), None, MAX_WIDTH_M, CFG)
    assert why == "wide: footprint 81 x 75 mm, wider than the gripper's 72 mm in every direction"
    long = block(0.50, 0.62, 0.0, 0.06, 0.0, 0.04)  # narrow enough one way
    assert ambiguity(track_of(5, long), None, MAX_WIDTH_M, CFG) is None


def test_a_graspable_box_with_few_points_is_judged_by_its_box():
    box = block(0.50, 0.55, 0.0, 0.08, 0.0, 0.04)
    assert ambiguity(track_of(4, box), box[:5], MAX_WIDTH_M, CFG) is None


def test_only_the_configured_rules_apply():
    ell = np.vstack([block(0.50, 0.56, 0.0, 0.02, 0.0, 0.04), block(0.50, 0.52, 0.0, 0.06, 0.0, 0.04)])
    assert ambiguity(track_of(1, ell), ell, MAX_WIDTH_M, CFG).startswith("non-convex")
    assert ambiguity(track_of(1, ell), ell, MAX_WIDTH_M, ScanConfig()) is None  # default: wide only
    wide = block(0.50, 0.581, 0.0, 0.075, 0.0, 0.04)
    assert ambiguity(track_of(2, wide), wide, MAX_WIDTH_M, ScanConfig(closer_look_rules=("non_convex",))) is None


def test_the_closer_look_parameters_are_validated():
    with pytest.raises(ConfigError, match="closer_look_min_solidity"):
        ScanConfig(closer_look_min_solidity=1.5).validate()
    with pytest.raises(ConfigError, match="closer_look_standoff_m"):
        ScanConfig(closer_look_standoff_m=0.0).validate()
    with pytest.raises(ConfigError, match="unknown rule"):
        ScanConfig(closer_look_rules=("wide", "round")).validate()
