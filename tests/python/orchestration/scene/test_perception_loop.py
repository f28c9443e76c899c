"""The perception loop's judge of a track for a grasp source that approaches from any side:
the scene cloud (a pass over the latest frame) is built only when the support rule is asked."""

import types

from grasp_pipeline.orchestration.scene.perception_loop import PerceptionLoop


def _track(height_ok: bool, resting: bool):
    est = types.SimpleNamespace(height_ok=height_ok, resting=resting, grasp_ok=False, width_ok=True,
                                notes=["floating: nothing under it"])
    return types.SimpleNamespace(tid=3, smoothed=est)


def _loop(monkeypatch):
    loop = PerceptionLoop(session=None)
    loop.width_guard = False
    built = []
    monkeypatch.setattr(loop, "scene_cloud", lambda: built.append(1))  # no cloud: None
    return loop, built


def test_a_resting_or_too_low_track_is_judged_without_the_scene_cloud(monkeypatch):
    loop, built = _loop(monkeypatch)
    assert loop.judge(_track(height_ok=True, resting=True)) == (True, [])
    assert loop.judge(_track(height_ok=False, resting=False)) == (False, ["floating: nothing under it"])
    assert built == []


def test_the_support_rule_asks_for_the_scene_cloud(monkeypatch):
    loop, built = _loop(monkeypatch)
    # without a cloud the support rule has no verdict: refused with the estimate's notes
    assert loop.judge(_track(height_ok=True, resting=False)) == (False, ["floating: nothing under it"])
    assert built == [1]
