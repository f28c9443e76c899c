"""The pipeline on a robot of one's own (grasp_pipeline.app.run_robot): the example of
examples/own_robot — an adapter on toy hardware, with a work-cell file of its own — picks both
of its boxes and places them in its tray; an adapter whose frames break the camera contract
(raw or float millimetre depth, no camera pose) ends the run at its first frame with a failed
report whose one-line error says what to fix, the arm never moved."""

from __future__ import annotations

import dataclasses
import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest

from grasp_pipeline.app import load_work_cell
from grasp_pipeline.robot.description import READY_Q

EXAMPLE = Path(__file__).resolve().parents[3] / "examples" / "own_robot"


def _example():
    spec = importlib.util.spec_from_file_location("own_robot_example", EXAMPLE / "run.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def example():
    return _example()


@pytest.fixture(scope="module")
def example_run(example, tmp_path_factory):
    out = tmp_path_factory.mktemp("own_robot")
    report, hardware = example.run_example(out, snapshots=False)
    return report, hardware, out


def test_the_example_robot_picks_both_boxes_and_places_them_in_its_tray(example, example_run):
    report, hardware, out = example_run
    assert report.status == "complete", report.error
    assert len(report.picks) == 2 and all(p.success and p.placed for p in report.picks), \
        [(p.failed_stage, p.message) for p in report.picks]
    cell = load_work_cell(example.WORK_CELL).cell
    floor, top = cell.tray_floor, float(cell.tray_center_m[2])
    for box in (b for b in hardware.boxes if b.movable):  # where the toy hardware says they are
        assert np.all(np.abs(box.center[:2] - floor.center[:2]) < 0.5 * floor.extents[:2]), box
        assert box.center[2] - 0.5 * box.size[2] == pytest.approx(top, abs=1e-6)
    data = json.loads((out / "report.json").read_text())
    assert data["status"] == "complete" and data["scene"]["robot"] == "OwnRobot"
    assert data["scene"]["work_cell"].endswith("work_cell.yaml")
    assert data["rough"]["scores"] == [] and data["scan"]["completed"]  # no ground truth on a robot
    assert not any("table plane" in w for w in data["warnings"]), data["warnings"]


def _failing_run(example, tmp_path, frame_change):
    class BrokenAdapter(example.OwnRobot):
        def capture(self):
            frame = super().capture()
            return dataclasses.replace(frame, **frame_change(self, frame))

    report, hardware = example.run_example(tmp_path, snapshots=False, robot_class=BrokenAdapter)
    assert report.status == "failed" and report.picks == [] and report.rough is None
    assert report.error.startswith("CameraFrameError: ") and "\n" not in report.error, report.error
    np.testing.assert_allclose(hardware.arm.q, READY_Q)  # nothing moved
    assert json.loads((tmp_path / "report.json").read_text())["error"] == report.error
    return report.error


def _raw(robot) -> np.ndarray:
    return robot.hw.camera_image()


def test_a_raw_depth_image_in_millimetres_is_refused_with_the_conversion_to_make(example, tmp_path):
    error = _failing_run(example, tmp_path, lambda robot, frame: {"depth": _raw(robot)})
    assert "uint16" in error and "millimetres" in error and "depth scale" in error


def test_a_float_depth_in_millimetres_is_refused(example, tmp_path):
    error = _failing_run(example, tmp_path, lambda robot, frame: {"depth": _raw(robot).astype(np.float32)})
    assert "millimetres?" in error and "metres" in error


def test_a_frame_without_the_camera_pose_is_refused_with_how_to_get_it(example, tmp_path):
    error = _failing_run(example, tmp_path, lambda robot, frame: {"T_world_camera": None})
    assert "pose T_world_camera is missing" in error and "hand-eye calibration" in error
