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
