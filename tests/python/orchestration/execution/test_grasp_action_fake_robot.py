"""The grasp action on a fake robot (no simulator): stages, held judgement from the gripper's
own signals, drops while carrying, recovery."""

import numpy as np
import pytest

from grasp_pipeline import _core
from grasp_pipeline.motion.occupancy import OrientedBox
from grasp_pipeline.motion.work_cell import WorkCell
from grasp_pipeline.orchestration import GraspAction, GraspConfig, Runtime
from grasp_pipeline.robot.protocols import Arm, Clock, ContactAllowance, ContactMonitor, Gripper

from ..fake_robot import FakeMotion, FakeRobot, fake_loop

TRAY = WorkCell(table=OrientedBox(np.array([0.5, 0, 0.19]), np.eye(3), np.array([0.6, 1.0, 0.02])),
                fixtures=(), tray_center_m=np.array([0.34, 0.58, 0.2]),
                tray_floor=OrientedBox(np.array([0.34, 0.58, 0.195]), np.eye(3), np.array([0.28, 0.28, 0.01])))


def top_down_grasp(x=0.5, y=0.0, z=0.225, width=0.05):
    R = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])  # approach -z, closing y
    return _core.BestGrasp(R, np.array([x, y, z]), width)


def run_action(robot, grasp, place=True, motion=None, config=None):
    rt = Runtime(robot)
    motion = motion or FakeMotion(robot)
    action = GraspAction(rt, fake_loop(robot), motion, config or GraspConfig(), work_cell=TRAY,
                         home_q=np.zeros(7))
    ok, msg = action.start(grasp, place=place)
    assert ok, msg
    return rt.run(action.task, 120.0), motion


def test_the_fake_robot_implements_the_protocols():
    robot = FakeRobot()
    for proto in (Clock, Arm, Gripper, ContactMonitor):
        assert isinstance(robot, proto)


def test_a_grasp_runs_every_stage_and_places():
    out, motion = run_action(FakeRobot(object_width_m=0.05), top_down_grasp())
    assert out.success and out.placed, out.message
    assert [s for s, _ in out.stages] == ["PRE_GRASP", "APPROACH", "CLOSE", "LIFT", "DONE", "PLACE"]
    assert out.stall_gap_m == pytest.approx(0.05, abs=1e-6)
    kinds = [k for k, _ in motion.executed]
    assert kinds[:3] == ["pre_grasp", "approach", "lift"] and kinds[-1] == "home"
    allowances = dict(motion.executed)
    assert allowances["approach"] is ContactAllowance.FINGERS
    assert allowances["lift"] is ContactAllowance.HELD_OBJECT
    assert allowances["place"] is ContactAllowance.HELD_OBJECT
    assert allowances["home"] is ContactAllowance.FINGERS  # may brush what lies in the tray


def test_the_fingers_are_at_the_grasp_opening_before_the_arm_moves():
    """The pre-grasp and approach are planned with the fingers at the grasp's opening (the
    width + open_margin_m), so the fingers get there before the arm leaves (fully open
    fingers from the previous pick would sweep past what the plan checked)."""
    robot = FakeRobot(object_width_m=0.03)
    assert robot.finger_gap_m == pytest.approx(0.08)
    out, motion = run_action(robot, top_down_grasp(width=0.03))
    assert out.success, out.message
    assert motion.gap_at_start["pre_grasp"] == pytest.approx(0.03 + GraspConfig().open_margin_m, abs=1e-3)


def test_closing_on_nothing_fails_close_and_recovers():
    out, motion = run_action(FakeRobot(object_width_m=None), top_down_grasp())
    assert not out.success and out.failed_stage == "CLOSE"
    assert "without stalling" in out.message or "fully closed" in out.message
    assert [k for k, _ in motion.executed][-2:] == ["retreat", "home"]


def test_a_stall_without_squeeze_force_is_not_a_grasp():
    out, _ = run_action(FakeRobot(object_width_m=0.05, squeeze_N=1.0), top_down_grasp())
    assert out.failed_stage == "CLOSE" and "nothing held" in out.message


def test_an_object_slipping_out_while_carrying_fails_place_as_a_drop():
    robot = FakeRobot(object_width_m=0.05)
    # lift + 2 s hold check end near t = 3.9 s; the object slips while carrying to the tray
    out, motion = run_action(robot, top_down_grasp(), config=GraspConfig(hold_check_s=0.5))
    t_carry = next(t for s, t in out.stages if s == "PLACE")
    robot2 = FakeRobot(object_width_m=0.05, slip_at_s=t_carry + 0.1)
    out2, motion2 = run_action(robot2, top_down_grasp(), config=GraspConfig(hold_check_s=0.5))
    assert not out2.success and out2.failed_stage == "PLACE"
    assert "dropped" in out2.message
    assert "home" in [k for k, _ in motion2.executed]


def test_an_object_turning_narrower_between_the_pads_is_still_held():
    """A rounded object that turns 5 mm narrower at full squeeze while carried is a hold (the
    gap alone once called it lost); the same gap with no squeeze left is a drop."""
    probe, _ = run_action(FakeRobot(object_width_m=0.05), top_down_grasp(),
                          config=GraspConfig(hold_check_s=0.5))
    t_lift = next(t for s, t in probe.stages if s == "LIFT")
    robot = FakeRobot(object_width_m=0.05, turn_at_s=t_lift + 0.05, turned_width_m=0.045)
    out, _ = run_action(robot, top_down_grasp(), config=GraspConfig(hold_check_s=0.5))
    assert out.success and out.placed, out.message
    assert out.stall_gap_m - 0.045 > GraspConfig().held_gap_drop_m
    gone = FakeRobot(object_width_m=0.05, slip_at_s=t_lift + 0.05)
    out2, _ = run_action(gone, top_down_grasp(), config=GraspConfig(hold_check_s=0.5))
    assert not out2.success and "squeeze 0.0 N" in out2.message


def test_a_lift_refused_inside_a_clearance_goes_straight_up_holding_the_object():
    robot = FakeRobot(object_width_m=0.05)
    motion = FakeMotion(robot)
    motion.refused_lines.add("lift")
    out, motion = run_action(robot, top_down_grasp(), motion=motion, config=GraspConfig(hold_check_s=0.5))
    assert out.success and out.placed, out.message
    assert motion.escapes == ["lift"]
    assert dict(motion.executed)["lift"] is ContactAllowance.HELD_OBJECT


def test_unplannable_candidates_are_refused_before_any_motion():
    from grasp_pipeline.motion.exceptions import PlanningFailedError

    robot = FakeRobot()

    class NoPath(FakeMotion):
        def plan_approach(self, T_grasp, T_pre):
            raise PlanningFailedError("blocked (fake)")

    out, motion = run_action(robot, top_down_grasp(), motion=NoPath(robot))
    assert out.failed_stage == "PRE_GRASP" and "no grasp candidate can be reached" in out.message
    assert [k for k, _ in motion.executed if k in ("pre_grasp", "approach")] == []


def test_a_tilted_grasp_lifts_along_the_table_normal_not_back_along_its_approach():
    """LIFT raises the object straight up from the table (the plane normal), whatever the
    approach: pulling back along a 45° approach would drag the object over the table."""
    from grasp_pipeline.orchestration.grasping.grasp import Grasp

    tilt = np.radians(45.0)
    approach = np.array([np.sin(tilt), 0.0, -np.cos(tilt)])
    grasp = Grasp.from_axes(approach, [0.0, 1.0, 0.0], [0.5, 0.0, 0.225], 0.05, tilt_deg=45.0)
    robot = FakeRobot(object_width_m=0.05)
    lifts = []

    class Recording(FakeMotion):
        def line(self, T, frame="tcp", kind="line", **kw):
            if kind == "lift":
                lifts.append((self.robot.tcp.copy(), np.asarray(T, float).copy()))
            return (yield from super().line(T, frame, kind, **kw))

    out, _ = run_action(robot, grasp, motion=Recording(robot))
    assert out.success, out.message
    (start, goal), = lifts
    moved = goal[:3, 3] - start[:3, 3]
    assert moved == pytest.approx([0.0, 0.0, GraspConfig().lift_height_m], abs=1e-9)
    assert goal[:3, :3] == pytest.approx(start[:3, :3])  # the hand keeps its attitude
