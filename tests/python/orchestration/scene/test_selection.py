"""method.md §5 selection on real core tracks (synthetic clusters, no simulator)."""

import logging

import numpy as np

from grasp_pipeline import _core
from grasp_pipeline.orchestration.scene.selection import Selector, perpendicular_grasp

PLANE = _core.Plane([0, 0, 1], -0.2)


def cube_points(cx, cy, side=0.05, z0=0.2, floating_m=0.0, seed=0, n=1500):
    rng = np.random.default_rng(seed)
    top = np.column_stack([rng.uniform(-side / 2, side / 2, n), rng.uniform(-side / 2, side / 2, n),
                           np.full(n, z0 + side + floating_m)])
    side_pts = np.column_stack([np.full(n // 2, side / 2), rng.uniform(-side / 2, side / 2, n // 2),
                                rng.uniform(z0 + 0.011 + floating_m, z0 + side + floating_m, n // 2)])
    return np.vstack([top, side_pts]) + np.array([cx, cy, 0.0])


def tracker_with(*clouds, t=0.0):
    tr = _core.Tracker(_core.ObbParams())
    ests = [_core.estimate_object(c, PLANE, _core.ObbParams(), band=0.01).estimate for c in clouds]
    tr.update(ests, [_core.ViewQuality.NADIR] * len(ests), t)
    return tr


def test_nothing_seen_yet():
    res = Selector().select(0.5, 0.0, [], None, PLANE)
    assert not res.ok and res.message == "nothing seen yet"


def test_far_selection_is_refused_and_keeps_the_previous_one():
    tr = tracker_with(cube_points(0.46, -0.10), cube_points(0.56, -0.03, seed=1))
    sel = Selector()
    ok = sel.select(0.56, -0.03, tr.tracks, tr.last_gate, PLANE)
    assert ok.ok and abs(ok.width_m - 0.05) < 0.002 and ok.grasp.score == 0.0
    R = np.asarray(ok.grasp.R)
    assert np.allclose(R[:, 0], [0, 0, -1], atol=1e-9) and abs(np.linalg.det(R) - 1) < 1e-9
    far = sel.select(1.5, 1.5, tr.tracks, tr.last_gate, PLANE)
    limit_mm = 2 * tr.last_gate * 1e3
    assert not far.ok and far.message.startswith("no object near (1.500, 1.500):")
    assert f"limit {limit_mm:.0f} mm" in far.message
    assert sel.anchor == (0.56, -0.03)  # the previous selection stays active


def test_single_object_uses_the_fallback_limit():
    tr = tracker_with(cube_points(0.5, 0.0))
    assert tr.last_gate is None
    assert Selector().select(1.5, 1.5, tr.tracks, None, PLANE).ok  # method.md §5 alone: no limit
    res = Selector(fallback_limit_m=0.1).select(1.5, 1.5, tr.tracks, None, PLANE)
    assert not res.ok and "limit 100 mm" in res.message


def test_guard_failure_message_is_the_hard_notes(caplog):
    tr = tracker_with(cube_points(0.46, -0.10, floating_m=0.03), cube_points(0.6, 0.1, seed=2))
    sel = Selector()
    res = sel.select(0.46, -0.10, tr.tracks, tr.last_gate, PLANE)
    assert not res.ok and res.message.startswith("floating/stacked: lowest point")
    assert sel.anchor is None


def test_every_frame_republishes_and_logs_failures_once(caplog):
    tr = tracker_with(cube_points(0.46, -0.10), cube_points(0.56, -0.03, seed=1))
    sel = Selector()
    assert sel.select(0.46, -0.10, tr.tracks, tr.last_gate, PLANE).ok
    for k in range(3):
        assert sel.on_frame(tr.tracks, tr.last_gate, PLANE, float(k)) is not None
    assert sel.published == 3
    with caplog.at_level(logging.WARNING, logger="grasp_pipeline.select"):
        for k in range(5):  # the object vanished: nothing near the anchor
            assert sel.on_frame([], None, PLANE, 10.0 + k) is None
    assert sum("not published" in r.message for r in caplog.records) == 1


def test_perpendicular_grasp_when_the_other_side_fits_the_gripper():
    tr = tracker_with(cube_points(0.46, -0.10), cube_points(0.56, -0.03, seed=1))
    track = tr.tracks[0]
    alt = perpendicular_grasp(track, PLANE, 0.06)
    assert alt is not None
    R = np.asarray(alt.R)
    best = _core.best_grasp_from_estimate(track.smoothed, PLANE)
    assert abs(np.dot(R[:, 2], np.asarray(best.R)[:, 2])) < 1e-6  # closing axis turned 90 deg
    assert abs(np.linalg.det(R) - 1) < 1e-9
    rng = np.random.default_rng(3)
    n = 2000
    for half_long_m, offered in [(0.035, False), (0.025, True)]:  # 70 mm > 60 mm; 50 mm fits
        cuboid = np.column_stack([rng.uniform(-0.015, 0.015, n), rng.uniform(-half_long_m, half_long_m, n),
                                  np.full(n, 0.24)]) + np.array([0.5, 0.1, 0])
        tr2 = tracker_with(cuboid, cube_points(0.3, -0.2, seed=4))
        cub = min(tr2.tracks, key=lambda t: abs(t.smoothed.center[0] - 0.5))
        alt = perpendicular_grasp(cub, PLANE, 0.06)
        assert (alt is not None) == offered
        if offered:
            assert abs(alt.width_m - 2 * half_long_m) < 0.003
