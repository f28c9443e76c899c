"""A picked object's track is a phantom only while it stays where the object was."""

from types import SimpleNamespace

import numpy as np

from grasp_pipeline.orchestration.config import GraspConfig
from grasp_pipeline.orchestration.execution.grasp_action import GraspAction


def _track(tid, x, y):
    return SimpleNamespace(tid=tid, smoothed=SimpleNamespace(center=np.array([x, y, 0.22])))


def _action(tracks):
    action = object.__new__(GraspAction)  # only the bookkeeping is under test
    action.config = GraspConfig()
    action.loop = SimpleNamespace(tracks=lambda: tracks)
    action.picked_at = {4: np.array([0.617, -0.056]), 2: np.array([0.539, -0.072])}
    return action


def test_a_lingering_track_of_a_picked_object_is_excluded():
    action = _action([_track(4, 0.617, -0.056), _track(7, 0.40, 0.10)])
    assert action.lingering_tids() == {4}


def test_a_picked_track_moved_onto_another_object_is_that_object_now():
    # (seen in the benchmark: a re-probed object's detection joined the lingering track of
    # the object picked before it, 140 mm away; excluding it hid the new target)
    action = _action([_track(4, 0.632, -0.195), _track(2, 0.5395, -0.0725)])
    assert action.lingering_tids() == {2}
