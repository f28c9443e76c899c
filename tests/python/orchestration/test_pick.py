"""One pick's selection step (:func:`grasp_pipeline.orchestration.pick._select_and_verify`): a
refusal after the closer look is a SELECT failure for a chosen object, and a decline (no
attempt: the arm has not moved to grasp) while clearing a table."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from grasp_pipeline.orchestration import pick
from grasp_pipeline.orchestration.scene.selection import SelectResult
from grasp_pipeline.results import PickResult


def _ctx(result: SelectResult, published: int = 0):
    selector = SimpleNamespace(published=published, clear=lambda: None)
    loop = SimpleNamespace(select=lambda x, y: result, selector=selector)
    rt = SimpleNamespace(spin_until=lambda done, timeout_s, look=False: done())
    scan = SimpleNamespace(select_verify_frames=1, stale_timeout_s=1.0)
    return SimpleNamespace(loop=loop, rt=rt, settings=SimpleNamespace(scan=scan))


@pytest.mark.parametrize("decline", [False, True])
def test_a_refused_selection_is_a_select_failure_or_a_decline(decline):
    row = PickResult(anchor=[0.5, 0.0])
    refusal = SelectResult(False, "floating/stacked: lowest point 67 mm above plane")
    assert pick._select_and_verify(_ctx(refusal), (0.5, 0.0), row, decline) is None
    assert row.failed_stage == "SELECT" and row.declined is decline and "floating" in row.message


@pytest.mark.parametrize("decline", [False, True])
def test_no_grasp_published_after_selection_is_a_select_failure_or_a_decline(decline):
    row = PickResult(anchor=[0.5, 0.0])
    assert pick._select_and_verify(_ctx(SelectResult(True, "ok", tid=3)), (0.5, 0.0), row, decline) is None
    assert row.failed_stage == "SELECT" and row.declined is decline and "no best grasp" in row.message


def test_an_accepted_selection_with_a_grasp_is_returned():
    row = PickResult(anchor=[0.5, 0.0])
    result = SelectResult(True, "selected", tid=3)
    assert pick._select_and_verify(_ctx(result, published=1), (0.5, 0.0), row, True) is result
    assert row.failed_stage is None and not row.declined and row.selected == "selected"


class _Cloud:
    def __init__(self, seen):
        self.seen = set(seen)

    def of(self, tid):
        return [(0.0, 0.0, 0.0)] if tid in self.seen else []


@pytest.mark.parametrize("quality, seen, looks", [
    ("NADIR", True, False),     # measured from above and in view: no re-probe
    ("NADIR", False, True),     # measured from above, but hidden from where the camera is now
    ("OBLIQUE", True, True),    # seen only obliquely
])
def test_the_re_probe_looks_from_above_at_an_oblique_or_hidden_target(monkeypatch, quality, seen, looks):
    from grasp_pipeline import _core

    track = SimpleNamespace(tid=4, quality=getattr(_core.ViewQuality, quality),
                            smoothed=SimpleNamespace(center=[0.5, 0.1, 0.23]))
    monkeypatch.setattr(pick, "check_selection", lambda *a: SimpleNamespace(kind="ok", track=track))
    selector = SimpleNamespace(fallback_limit_m=0.05, judge=None)
    loop = SimpleNamespace(tracks=lambda: [track], gate_m=0.05, plane=None, selector=selector,
                           scene_cloud=lambda: _Cloud([4] if seen else []))
    centre = pick._reprobe_centre(SimpleNamespace(loop=loop), (0.5, 0.1))
    assert (centre is not None) is looks
    if looks:
        assert list(centre) == [0.5, 0.1, 0.23]


class _Frames:
    """A camera whose frames show track 4 from the ``shows_from``-th frame on (another track
    of the same object takes its points before that)."""

    def __init__(self, shows_from: int):
        self.frames, self.shows_from, self.looked = 0, shows_from, []

    def cloud(self):
        return _Cloud([4] if self.frames >= self.shows_from else [])

    def spin_until(self, done, timeout_s, look=False):
        self.looked.append(look)
        for _ in range(int(round(timeout_s * 30))):  # 30 Hz frames while looking
            if done():
                return True
            self.frames += 1
        return done()


@pytest.mark.parametrize("shows_from, found, looked", [
    (0, True, False),   # in the latest frame already: no wait, no frame
    (3, True, True),    # the third frame shows it
    (50, False, True),  # not within the timeout: the grasp source gets the latest frame
])
def test_grasps_are_asked_for_once_a_frame_shows_the_selected_object(shows_from, found, looked):
    cam = _Frames(shows_from)
    loop = SimpleNamespace(scene_cloud=cam.cloud)
    ctx = SimpleNamespace(loop=loop, rt=SimpleNamespace(spin_until=cam.spin_until),
                          settings=SimpleNamespace(scan=SimpleNamespace(target_view_timeout_s=0.3)))
    assert pick._wait_in_view(ctx, 4) is found
    assert cam.looked == ([True] if looked else [])
    assert cam.frames == (min(shows_from, 9) if looked else 0)
