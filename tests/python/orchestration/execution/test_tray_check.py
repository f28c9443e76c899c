"""The robot's verdict "placed" from a look into the tray (synthetic points)."""

import numpy as np
import pytest

from grasp_pipeline.orchestration.execution.place_config import PlaceConfig
from grasp_pipeline.orchestration.execution.tray import TrayContents, TrayGeometry
from grasp_pipeline.orchestration.execution.tray_check import arrival_verdict, look_pose
from grasp_pipeline.robot import description as rm

from .tray_cell import CELL, FLOOR_Z, box_points, floor_points, solid_points

CFG = PlaceConfig()


def released_at(tray, x, y):
    """(grid, heights before, footprint, top) for a 4 x 4 x 5 cm object released over (x, y)."""
    grid = tray.geometry.grid(tray.cell_m)
    before = tray.heights(grid)
    tray.add_released(solid_points(0.04, 0.04, 0.05) + [x, y, FLOOR_Z + 0.04])
    after = tray.heights(grid)
    return grid, before, after > before, float(after[after > before].max())


@pytest.fixture
def tray():
    t = TrayContents(TrayGeometry.from_work_cell(CELL), 0.005, CFG.seen_min_height_m)
    t.add_released(solid_points(0.05, 0.05, 0.06) + [0.28, 0.52, FLOOR_Z + 0.03])  # an earlier one
    return t


def test_the_object_seen_where_it_was_released_is_placed(tray):
    grid, before, footprint, top = released_at(tray, 0.40, 0.64)
    seen = np.vstack([floor_points(), box_points(0.28, 0.52, 0.05, 0.05, 0.06),
                      box_points(0.405, 0.635, 0.04, 0.04, 0.05)])  # it landed a little aside
    v = arrival_verdict(grid, before, footprint, top, seen, CFG)
    assert v.placed and v.new_area_m2 >= CFG.arrived_min_area_m2, v.message


def test_an_object_that_fell_out_is_not_placed_and_the_message_says_why(tray):
    grid, before, footprint, top = released_at(tray, 0.40, 0.64)
    seen = np.vstack([floor_points(), box_points(0.28, 0.52, 0.05, 0.05, 0.06)])  # only the earlier one
    v = arrival_verdict(grid, before, footprint, top, seen, CFG)
    assert not v.placed
    assert "the object is not seen in the tray: 0.0 cm2 of new contents within 50 mm" in v.message


def test_the_earlier_objects_do_not_count_as_the_new_one(tray):
    grid, before, footprint, top = released_at(tray, 0.31, 0.52)  # released next to the earlier one
    seen = np.vstack([floor_points(), box_points(0.28, 0.52, 0.05, 0.05, 0.06)])
    assert not arrival_verdict(grid, before, footprint, top, seen, CFG).placed


def test_an_object_still_hanging_from_the_hand_is_not_placed(tray):
    grid, before, footprint, top = released_at(tray, 0.40, 0.64)
    seen = np.vstack([floor_points(), box_points(0.28, 0.52, 0.05, 0.05, 0.06),
                      box_points(0.40, 0.64, 0.04, 0.04, 0.15)])  # 10 cm above where it would lie
    v = arrival_verdict(grid, before, footprint, top, seen, CFG)
    assert not v.placed and "the object is not seen in the tray" in v.message


def test_without_a_view_of_the_spot_nothing_is_confirmed(tray):
    grid, before, footprint, top = released_at(tray, 0.40, 0.64)
    v = arrival_verdict(grid, before, footprint, top, None, CFG)
    assert not v.placed and "the camera saw only 0 %" in v.message
    far_half = floor_points()[floor_points()[:, 1] < 0.55]
    assert not arrival_verdict(grid, before, footprint, top, far_half, CFG).placed


def test_the_look_pose_puts_the_camera_straight_above_the_point():
    model = rm.load_robot_model()
    T = look_pose(model, 0.7, (0.34, 0.58), 0.55)
    T_cam = T @ np.linalg.inv(rm.flange_T_tcp(model)) @ rm.flange_T_camera(model)
    assert np.allclose(T_cam[:3, 3], [0.34, 0.58, 0.55], atol=1e-9)
    assert np.allclose(T[:3, 2], [0.0, 0.0, -1.0])  # approach (and the optical axis) down
    assert np.allclose(T_cam[:3, 2], [0.0, 0.0, -1.0], atol=1e-9)
