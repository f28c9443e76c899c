"""Default targets: which perceived tracks are picked when the user names none."""

from types import SimpleNamespace

from grasp_pipeline import _core
from grasp_pipeline.orchestration.config import GraspConfig
from grasp_pipeline.orchestration.scene.targets import default_targets, rough_view_ids

OBLIQUE, NADIR = _core.ViewQuality.OBLIQUE, _core.ViewQuality.NADIR


def _track(tid, x, y, quality=OBLIQUE):
    est = SimpleNamespace(center=[x, y, 0.22], grasp_ok=True, notes=[])
    return SimpleNamespace(tid=tid, smoothed=est, quality=quality)


class _Cell:
    def pick_target_note(self, xy, margin_m):
        return None


def test_track_that_took_a_lost_rough_tracks_place_is_picked():
    """Sparse bench scene 46 (seed 1520975963): the tracker lost rough track #0 during the
    scan and found the cube again as #3 (oblique): it must still be a target."""
    rough = {0: (0.6315, 0.2091), 1: (0.5386, -0.1741)}
    after = [_track(1, 0.5386, -0.1741, NADIR), _track(3, 0.6322, 0.2098)]
    ids = rough_view_ids(rough, after, GraspConfig().rough_takeover_m)
    assert ids == {1, 3}
    targets, skipped = default_targets(after, _Cell(), 0.03, ids)
    assert len(targets) == 2 and skipped == []


def test_glimpse_far_from_any_lost_rough_track_is_still_skipped():
    rough = {0: (0.6315, 0.2091), 1: (0.5386, -0.1741)}
    after = [_track(1, 0.5386, -0.1741, NADIR), _track(3, 0.70, 0.30)]  # #0 gone, #3 elsewhere
    ids = rough_view_ids(rough, after, GraspConfig().rough_takeover_m)
    assert ids == {1}
    targets, skipped = default_targets(after, _Cell(), 0.03, ids)
    assert targets == [(0.5386, -0.1741)]
    assert skipped[0]["tid"] == 3 and "first seen during the scan" in skipped[0]["why"]


def test_new_track_near_a_rough_track_that_still_exists_is_not_a_takeover():
    rough = {0: (0.60, 0.20)}
    after = [_track(0, 0.60, 0.20, NADIR), _track(4, 0.61, 0.20)]
    assert rough_view_ids(rough, after, GraspConfig().rough_takeover_m) == {0}
