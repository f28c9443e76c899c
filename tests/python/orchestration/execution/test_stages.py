"""The pick stages (orchestration/execution/stages.py): typed members that read, compare and
serialize as the plain names the reports have always held."""

import json
import pickle

from grasp_pipeline.orchestration import GraspStage, Stage
from grasp_pipeline.report.serialize import dumps
from grasp_pipeline.results import GraspOutcome, PickResult

from ..fake_robot import FakeRobot
from .test_grasp_action_fake_robot import run_action, top_down_grasp


def test_every_stage_is_its_own_name():
    assert [s.value for s in Stage] == [s.name for s in Stage]
    assert GraspStage is Stage


def test_a_stage_reads_as_its_name_in_text_and_comparisons():
    s = Stage.PRE_GRASP
    assert s == "PRE_GRASP" and "PRE_GRASP" == s and s != "APPROACH"
    assert str(s) == f"{s}" == "%s" % s == "PRE_GRASP"
    assert f"{s:>10}" == " PRE_GRASP"
    assert {"PRE_GRASP": 1}[s] == 1 and {s: 1}["PRE_GRASP"] == 1
    assert s.lower() == "pre_grasp"
    assert pickle.loads(pickle.dumps(s)) is s


def test_reports_with_stages_are_the_reports_with_their_names():
    typed = PickResult(anchor=[0.5, 0.0], failed_stage=Stage.LIFT,
                       stages=[(Stage.PRE_GRASP, 1.25), (Stage.LIFT, 2.5)])
    plain = PickResult(anchor=[0.5, 0.0], failed_stage="LIFT",
                       stages=[("PRE_GRASP", 1.25), ("LIFT", 2.5)])
    assert dumps(typed) == dumps(plain)
    assert json.dumps({Stage.LIFT: Stage.CLOSE}) == '{"LIFT": "CLOSE"}'


def test_the_grasp_action_produces_stages():
    out, _ = run_action(FakeRobot(object_width_m=None), top_down_grasp())
    assert isinstance(out, GraspOutcome) and out.failed_stage is Stage.CLOSE
    assert all(isinstance(s, Stage) for s, _ in out.stages)
    assert out.message.startswith("CLOSE failed: ")
