"""The composition root on any robot: an adapter without every protocol member is refused
before anything is built, naming what it lacks; a built system feeds the robot's frames to
perception and stops listening when closed (the robot stays the caller's)."""

from __future__ import annotations

import importlib.util
from pathlib import Path
from types import SimpleNamespace

import pytest

from grasp_pipeline.app.robot_system import ROBOT_SECTIONS, build_robot_system
from grasp_pipeline.app.work_cell_file import load_work_cell
from grasp_pipeline.exceptions import RobotAdapterError
from grasp_pipeline.settings import load_settings

EXAMPLE = Path(__file__).resolve().parents[3] / "examples" / "own_robot"


def test_an_adapter_without_every_protocol_member_is_refused_naming_them():
    partial = SimpleNamespace(q=None, qd=None, time_s=0.0, timestep_s=0.01, step=lambda n=1: None)
    with pytest.raises(RobotAdapterError) as info:
        build_robot_system(partial, load_work_cell(), load_settings(ROBOT_SECTIONS))
    msg = str(info.value)
    assert "\n" not in msg and "docs/real_robot.md" in msg
    assert "camera_pose" in msg and "unexpected_contacts" in msg and "set_gripper" in msg
    assert "step" not in msg.split("lacks ")[1].split(" of the")[0].split(", ")


def test_a_built_system_perceives_the_robots_frames_and_lets_go_of_the_robot_when_closed():
    spec = importlib.util.spec_from_file_location("own_robot_example_system", EXAMPLE / "run.py")
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    robot, _ = example.build_robot()
    system = build_robot_system(robot, load_work_cell(example.WORK_CELL), load_settings(ROBOT_SECTIONS))
    assert len(robot._listeners) == 1
    system.rt.spin(0.5)  # the rough view's look
    assert system.loop.frames >= 5 and system.loop.plane is not None
    assert abs(system.loop.plane.height_m - 0.20) < 0.01
    system.close()
    assert robot._listeners == []
