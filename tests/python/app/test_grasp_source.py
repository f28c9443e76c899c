"""A different grasp source plugged into the run: a fixed list of poses picks the blue cube
(real MuJoCo physics, OMPL, TOPP-RA; nothing of the geometric grasp is used)."""

import math

import numpy as np

from grasp_pipeline.app.run import run_pipeline
from grasp_pipeline.orchestration import FixedGraspSource

BLUE_CUBE_XY = (0.56, -0.03)
BLUE_CUBE_CENTRE_M = (0.56, -0.03, 0.225)   # method.md §8: 5 cm cube on the 0.2 m table
BLUE_CUBE_YAW_DEG = 20.0


def known_grasp():
    """Top-down, closing across the cube's faces: column 0 approach (down), column 2 closing."""
    c, s = math.cos(math.radians(BLUE_CUBE_YAW_DEG)), math.sin(math.radians(BLUE_CUBE_YAW_DEG))
    R = np.column_stack([[0.0, 0.0, -1.0], [-s, c, 0.0], [c, s, 0.0]])
    return R, np.array(BLUE_CUBE_CENTRE_M), 0.05


def test_a_fixed_pose_source_picks_the_object(tmp_path):
    source = FixedGraspSource.from_poses([known_grasp()])
    report = run_pipeline(scene="reference", select=[BLUE_CUBE_XY], out_dir=tmp_path, video=False,
                          scan=False, grasp_source=source)
    pick = report.picks[0]
    assert pick.grasp_source == "fixed"
    assert pick.success and pick.placed, pick.message
    assert pick.object == "blue_cube" and pick.lift_m >= 0.05


def test_a_source_with_no_grasp_near_the_object_fails_the_pick_cleanly(tmp_path):
    R, p, w = known_grasp()
    source = FixedGraspSource.from_poses([(R, p + np.array([0.3, 0.0, 0.0]), w)])
    report = run_pipeline(scene="reference", select=[BLUE_CUBE_XY], out_dir=tmp_path, video=False,
                          scan=False, grasp_source=source)
    pick = report.picks[0]
    assert not pick.success and pick.failed_stage == "GRASP"
    assert "proposed no grasp" in pick.message
