"""The support rule (docs/method.md §2.8, extends method.md §2.6) on small synthetic clouds."""

import numpy as np

from grasp_pipeline import _core
from grasp_pipeline.orchestration.config import GraspFitConfig
from grasp_pipeline.orchestration.grasping.support import judge_graspable, support_verdict

from ..clouds import ENV, block, scene, table, track_of

CFG = GraspFitConfig()


def test_a_cube_with_the_table_seen_under_it_is_floating():
    cube = block(0.50, 0.55, 0.0, 0.05, 0.03, 0.08)
    v = support_verdict(0, scene((0, cube), (ENV, table())), CFG)
    assert not v.supported and v.why.startswith("floating: lower surfaces seen under")


def test_nothing_perceived_under_or_around_it_is_floating():
    cube = block(0.50, 0.55, 0.0, 0.05, 0.03, 0.08)
    v = support_verdict(0, scene((0, cube)), CFG)
    assert not v.supported and v.why.startswith("floating: nothing perceived under it")


def test_a_mug_seen_only_by_its_rim_stands_on_the_table():
    th = np.linspace(0, 2 * np.pi, 240, endpoint=False)
    rim = np.column_stack([0.5 + 0.04 * np.cos(th), 0.04 * np.sin(th), np.full(th.size, 0.09)])
    v = support_verdict(0, scene((0, rim), (ENV, table(holes=[(0.455, 0.545, -0.045, 0.045)]))), CFG)
    assert v.supported and "stands on the table" in v.why


def test_a_box_on_a_box_rests_on_the_lower_one():
    lower = block(0.48, 0.58, -0.03, 0.07, 0.0, 0.04)
    lower = lower[~((lower[:, 0] > 0.51) & (lower[:, 0] < 0.55) & (lower[:, 1] > 0.0) & (lower[:, 1] < 0.04))]
    upper = block(0.51, 0.55, 0.0, 0.04, 0.04, 0.08)
    v = support_verdict(0, scene((0, upper), (1, lower), (ENV, table(holes=[(0.48, 0.58, -0.03, 0.07)]))), CFG)
    assert v.supported and v.support_tid == 1 and "resting on object #1" in v.why


def test_without_points_of_the_object_the_spec_verdict_stands():
    other = block(0.50, 0.55, 0.0, 0.05, 0.0, 0.05)
    cloud = scene((1, other), (ENV, table()))
    assert support_verdict(0, cloud, CFG) is None
    ok, notes = judge_graspable(track_of(0, other), cloud, CFG)
    assert not ok and notes[0].startswith("floating/stacked")


def test_judge_on_a_core_track_refused_by_spec_26_but_supported():
    # the core's estimate refuses the cube (its lowest visible point is 30 mm up: a rim-like view)
    cube = block(0.50, 0.55, 0.0, 0.05, 0.03, 0.08)
    plane = _core.Plane([0, 0, 1], 0.0)
    est = _core.estimate_object(cube, plane, _core.ObbParams(), band=0.01).estimate
    tr = _core.Tracker(_core.ObbParams())
    tr.update([est], [_core.ViewQuality.NADIR], 0.0)
    track = tr.tracks[0]
    assert not track.smoothed.grasp_ok and not track.smoothed.resting
    hidden = scene((track.tid, cube), (ENV, table(holes=[(0.495, 0.555, -0.005, 0.055)])))
    assert judge_graspable(track, hidden, CFG) == (True, [])
    seen_through = scene((track.tid, cube), (ENV, table()))
    ok, notes = judge_graspable(track, seen_through, CFG)
    assert not ok and notes[0].startswith("floating")
    assert judge_graspable(track, None, CFG) == (False, list(track.smoothed.notes))
