"""PLACE on the fake robot: a lowering that stops early releases low or retries elsewhere —
never from high; the verdict "placed" needs the object seen in the tray."""

import numpy as np
import pytest

from grasp_pipeline.orchestration import GraspAction, GraspConfig, Runtime
from grasp_pipeline.orchestration.execution.place_config import PlaceConfig

from ..fake_robot import FakeMotion, FakeRobot, fake_loop
from .test_grasp_action_fake_robot import TRAY, top_down_grasp

FLOOR_Z = 0.2
CFG = PlaceConfig()


def run_place(robot, motion=None):
    rt = Runtime(robot)
    motion = motion or FakeMotion(robot)
    action = GraspAction(rt, fake_loop(robot), motion, GraspConfig(hold_check_s=0.3), work_cell=TRAY,
                         home_q=np.zeros(7), place_config=CFG)
    releases = []
    set_gripper = robot.set_gripper

    def spy(width_m, effort_N=None, speed_mps=None):  # where and when the fingers open wider than held
        if width_m > robot.finger_gap_m + 1e-3 and robot.object_width_m is not None:
            releases.append((robot.time_s, robot.tcp[:3, 3].copy()))
        set_gripper(width_m, effort_N, speed_mps)

    robot.set_gripper = spy
    ok, msg = action.start(top_down_grasp(), place=True)
    assert ok, msg
    out = rt.run(action.task, 200.0)
    action.releases = [(t, p) for t, p in releases if p[1] > 0.3]  # over the tray (not at the grasp)
    return out, motion, action, [p for _, p in action.releases]


#: The fake perceives no points: the held object is the box between the fingers as deep as
#: the TCP stood above the table (the grasp at z = 0.225 over the table at 0.2).
BOTTOM_BELOW_TCP_M = 0.025


def bottom_above_floor_m(tcp_xyz, action):
    """How high the held object's bottom was over the tray floor at a TCP position."""
    return tcp_xyz[2] - BOTTOM_BELOW_TCP_M - FLOOR_Z


def run_place_blocked_below(lines_z_m: float, poses_z_m: float = -np.inf):
    """PLACE where the planner refuses straight lines (and joint-space goals) ending lower
    than the given TCP heights."""
    robot = FakeRobot(object_width_m=0.05)
    motion = FakeMotion(robot)
    motion.lines_blocked_below_z_m = lines_z_m
    motion.poses_blocked_below_z_m = poses_z_m
    return run_place(robot, motion)


def test_a_plain_place_releases_low_and_sees_the_object_arrive():
    out, motion, action, releases = run_place(FakeRobot(object_width_m=0.05))
    assert out.success and out.placed, out.message
    assert len(releases) == 1
    assert bottom_above_floor_m(releases[0], action) == pytest.approx(CFG.release_clearance_m, abs=1e-6)
    assert "tray_look" in [k for k, _ in motion.executed]
    assert list(motion.obstacles) == ["placed/0"]  # the planner knows what lies in the tray now


def test_a_lowering_the_planner_stops_a_little_early_releases_at_the_lowest_plannable_height():
    # lines ending less than 47 mm above the floor are refused: the object's bottom 22 mm up
    out, motion, action, releases = run_place_blocked_below(FLOOR_Z + 0.047)
    assert out.success and out.placed, out.message
    drop = bottom_above_floor_m(releases[0], action)
    assert 0.022 <= drop <= 0.022 + CFG.lower_step_m and drop <= CFG.release_max_drop_m


def test_a_lowering_stopped_high_by_the_planner_never_releases_there_and_fails_after_the_attempts():
    # the bottom could not come below 75 mm, by any motion
    out, motion, action, releases = run_place_blocked_below(FLOOR_Z + 0.10, FLOOR_Z + 0.10)
    assert not out.placed and out.failed_stage == "PLACE"
    assert ("could not lower the object to within 30 mm of what lies under it at "
            f"{CFG.lower_attempts} spot(s)") in out.message
    assert [k for k, _ in motion.executed].count("place") == CFG.lower_attempts  # three spots tried
    assert "place_down" not in [k for k, _ in motion.executed]
    # the place never let go: only the recovery after the failure opens the fingers
    assert all(t >= out.release_time_s for t, _ in action.releases)


def test_a_lowering_stopped_high_by_a_contact_backs_up_and_places_elsewhere():
    robot = FakeRobot(object_width_m=0.05)
    motion = FakeMotion(robot)
    motion.stop_kinds["place_down"] = 0.2  # the first lowering stops a fifth of the way down
    out, motion, action, releases = run_place(robot, motion)
    assert out.success and out.placed, out.message
    kinds = [k for k, _ in motion.executed]
    assert kinds.count("place_down") == 2 and "place_back_up" in kinds
    assert kinds.index("place_back_up") < len(kinds) - 1 - kinds[::-1].index("place")  # then to another spot
    assert len(releases) == 1
    assert bottom_above_floor_m(releases[0], action) == pytest.approx(CFG.release_clearance_m, abs=1e-6)


def test_a_lowering_stopped_high_with_the_hand_held_up_is_a_touchdown_and_releases_there():
    # the object hangs lower than the model of it: it rests on the floor while the model puts
    # its bottom 60 mm up, and the arm, held up by it, stops with a tracking error
    robot = FakeRobot(object_width_m=0.05)
    motion = FakeMotion(robot)
    motion.stop_kinds["place_down"] = 0.4
    motion.stop_held_up_m["place_down"] = 0.02
    out, motion, action, releases = run_place(robot, motion)
    assert out.success and out.placed, out.message
    kinds = [k for k, _ in motion.executed]
    assert kinds.count("place_down") == 1 and "place_back_up" not in kinds
    assert len(releases) == 1
    assert bottom_above_floor_m(releases[0], action) > CFG.release_max_drop_m  # where the model put it


def test_a_tracking_stop_without_the_hand_held_up_backs_up_and_places_elsewhere():
    robot = FakeRobot(object_width_m=0.05)
    motion = FakeMotion(robot)
    motion.stop_kinds["place_down"] = 0.4
    motion.stop_held_up_m["place_down"] = 0.5 * CFG.touch_down_m  # a sag, not a support
    out, motion, action, releases = run_place(robot, motion)
    assert out.success and out.placed, out.message
    kinds = [k for k, _ in motion.executed]
    assert kinds.count("place_down") == 2 and "place_back_up" in kinds
    assert bottom_above_floor_m(releases[0], action) == pytest.approx(CFG.release_clearance_m, abs=1e-6)


def test_a_lowering_stopped_low_by_a_contact_releases_there():
    robot = FakeRobot(object_width_m=0.05)
    motion = FakeMotion(robot)
    motion.stop_kinds["place_down"] = 0.97  # stops with the bottom a little above its aim (8 mm)
    out, motion, action, releases = run_place(robot, motion)
    assert out.success and out.placed, out.message
    assert [k for k, _ in motion.executed].count("place_down") == 1
    assert CFG.release_clearance_m < bottom_above_floor_m(releases[0], action) <= CFG.release_max_drop_m


def test_an_object_not_seen_in_the_tray_after_the_release_fails_place():
    out, motion, action, releases = run_place(FakeRobot(object_width_m=0.05, released_vanish=True))
    assert not out.placed and out.failed_stage == "PLACE"
    assert "the object is not seen in the tray" in out.message
    # it was released low; the look found nothing there (the recovery opens fully afterwards)
    assert bottom_above_floor_m(releases[0], action) == pytest.approx(CFG.release_clearance_m, abs=1e-6)


def test_a_carry_up_out_of_reach_carries_from_where_the_arm_is():
    robot = FakeRobot(object_width_m=0.05)
    motion = FakeMotion(robot)
    motion.refused_lines.add("carry_up")

    def unreachable_above_the_table(T, q_from=None, frame="tcp"):
        from grasp_pipeline.motion.exceptions import UnreachablePoseError
        from ..fake_robot import FakeTrajectory

        if T[1, 3] < 0.3:  # over the table: out of reach up there (fake)
            raise UnreachablePoseError("pose unreachable (fake)")
        return FakeTrajectory(np.asarray(T))

    motion.plan_pose = unreachable_above_the_table
    out, motion, action, releases = run_place(robot, motion)
    assert out.success and out.placed, out.message
    assert "carry_up" not in [k for k, _ in motion.executed]


def test_a_straight_lowering_the_planner_stops_high_goes_down_in_joint_space():
    # the straight line down crosses a wrist singularity 75 mm up; a joint-space motion to the
    # same low pose can be planned
    out, motion, action, releases = run_place_blocked_below(FLOOR_Z + 0.10)
    assert out.success and out.placed, out.message
    assert [k for k, _ in motion.executed].count("place_down") == 1
    assert bottom_above_floor_m(releases[0], action) == pytest.approx(CFG.release_clearance_m, abs=1e-6)
