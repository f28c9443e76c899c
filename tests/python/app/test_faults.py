"""Faults the pipeline survives, in the real simulation, each with its outcome in the report:
an unseen obstacle stops an approach (the arm recovers, later picks work), camera frames stop
or turn to NaN, an object slips out while carried, the gripper does not close, the planner
has no time."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from grasp_pipeline.app.run import run_pipeline
from grasp_pipeline.app.sim_system import SECTIONS
from grasp_pipeline.orchestration.events import StageEvent
from grasp_pipeline.settings import load_settings
from grasp_pipeline.sim.scene_spec import ObjectSpec
from grasp_pipeline.sim.scenes import reference_scene

BLUE_CUBE = (0.56, -0.03)
CYLINDER = (0.52, 0.09)


def _run(tmp_path, select, scene="reference", prepare=None, sets=(), scan=False):
    settings = load_settings(SECTIONS, None, list(sets))
    return run_pipeline(scene=scene, select=select, out_dir=tmp_path, json_path=tmp_path / "r.json",
                        video=False, scan=scan, settings=settings, prepare=prepare)


def test_an_unseen_obstacle_stops_the_approach_and_the_next_pick_still_works(tmp_path):
    ref = reference_scene()
    # a small glass plate 4 cm above the blue cube: the camera sees through it, the hand does not
    plate = ObjectSpec("glass_plate", "cuboid", (0.03, 0.03, 0.004), (0.56, -0.03, 0.29),
                       camera_visible=False, fixed=True)
    scene = dataclasses.replace(ref, objects=ref.objects + (plate,))
    report = _run(tmp_path, [BLUE_CUBE, CYLINDER], scene=scene)
    first, second = report.picks
    assert first.failed_stage == "APPROACH" and "execution stopped" in first.message
    assert second.success and second.placed, second.message
    assert report.status == "complete"


def _stop_frames_at_stage(stage: str):
    def prepare(system):
        def on_stage(ev):
            if ev.name == stage:
                system.world.poll_frame = lambda: None  # the camera died
        system.events.subscribe(StageEvent, on_stage)
    return prepare


def test_frames_stopping_mid_grasp_finish_that_grasp_and_refuse_the_next_pick(tmp_path):
    report = _run(tmp_path, [BLUE_CUBE, CYLINDER], prepare=_stop_frames_at_stage("APPROACH"))
    first, second = report.picks
    assert first.success, first.message  # planned on fresh data before the camera died
    assert not second.success and second.failed_stage == "SELECT"
    assert "no best grasp arrived" in second.message


def test_frames_stopping_mid_scan_fail_the_probes_and_return_the_arm(tmp_path):
    report = _run(tmp_path, [], prepare=_stop_frames_at_stage("rough_view_done"), scan=True)
    scan = report.scan
    assert not any(p.nadir for p in scan.probes)
    assert all("no NADIR estimate" in p.message for p in scan.probes)
    assert scan.returned_to_start


def test_a_burst_of_nan_frames_and_empty_clouds_changes_nothing(tmp_path):
    def prepare(system):
        world, real = system.world, system.world.poll_frame

        def poll():
            f = real()
            if f is not None and 0.1 <= f.time_s < 0.3:  # ~6 frames all NaN, then empty-ish
                pts = np.full_like(f.points_world, np.nan)
                f = dataclasses.replace(f, points_world=pts)
            return f
        world.poll_frame = poll
    report = _run(tmp_path, [BLUE_CUBE], prepare=prepare)
    assert abs(report.plane["height_m"] - 0.2) < 1e-3
    assert report.picks[0].success, report.picks[0].message


def test_an_object_slipping_out_while_carried_is_a_drop_at_place_and_the_run_goes_on(tmp_path):
    def prepare(system):
        m = system.world.model

        def on_stage(ev):
            if ev.name == "PLACE":  # cube and finger pads turn to ice (MuJoCo takes the max)
                for name in ("obj_blue_cube", "leftfinger_pad", "rightfinger_pad",
                             "leftfinger_col0", "rightfinger_col0"):
                    m.geom_friction[m.geom(name).id, 0] = 0.0
        system.events.subscribe(StageEvent, on_stage)
    report = _run(tmp_path, [BLUE_CUBE, CYLINDER], prepare=prepare)
    first, second = report.picks
    assert not first.success and first.failed_stage == "PLACE" and "dropped" in first.message
    assert second.success, second.message


def test_a_gripper_that_does_not_close_fails_close_with_a_reason(tmp_path):
    def prepare(system):
        world, real = system.world, system.world.set_gripper
        # the fingers stop 6 cm apart whatever is commanded (a jammed gripper)
        world.set_gripper = lambda width_m, **kw: real(max(width_m, 0.06), **kw)
    report = _run(tmp_path, [BLUE_CUBE], prepare=prepare)
    pick = report.picks[0]
    assert pick.failed_stage == "CLOSE" and "nothing held" in pick.message


@pytest.mark.parametrize("sets", [["motion.try_direct_first=false", "motion.planning_time_s=0.00001",
                                   "motion.num_planning_attempts=1"]])
def test_a_planner_without_time_fails_cleanly(tmp_path, sets):
    report = _run(tmp_path, [BLUE_CUBE], sets=sets, scan=True)
    assert report.status == "complete"
    assert "failed to move" in report.scan.failure
    assert not report.picks[0].success and report.picks[0].message
