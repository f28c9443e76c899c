"""method.md §4 (tracker) through the bindings: gate, association, two-pass yaw
disambiguation (the alternating 0°/90° sequence), monotone quality, window restarts,
two-level retirement.
"""

import math

import numpy as np
import pytest

import synthetic_clouds as sc
from grasp_pipeline import _core

TABLE = _core.Plane([0, 0, 1], -0.2)
OBL = _core.ViewQuality.OBLIQUE
NAD = _core.ViewQuality.NADIR


def obb(**kw):
    p = _core.ObbParams()
    for k, v in kw.items():
        setattr(p, k, v)
    return p


def square(xy, yaw_deg=20.0, side=0.05, size=None, seed=0, n=700):
    return sc.box_top(xy, size or (side, side), 0.25, yaw_rad=math.radians(yaw_deg), n=n, seed=seed)


def estimate(pts, theta_prev=None, params=None):
    res = _core.estimate_object(pts, TABLE, params or obb(), theta_prev=theta_prev, band=0.01)
    assert res.estimate is not None, res.failure
    return res.estimate


def est_at(xy, **kw):
    return estimate(square(xy, **kw))


def true_extent(pts, theta):
    """Extent of the points along the in-plane direction theta (level table: u = x, v = y)."""
    return _core.extent_along(list(pts[:, 0]), list(pts[:, 1]), theta)


# --------------------------------------------------------------------------------------
# gate and association


def test_gate_is_a_fraction_of_the_min_pairwise_distance():
    assert _core.Tracker.gate_for([], 0.5) is None
    assert _core.Tracker.gate_for([np.array([0.5, 0, 0.2])], 0.5) is None
    c = [np.array([0.4, 0, 0.2]), np.array([0.5, 0, 0.2]), np.array([0.5, 0.3, 0.2])]
    assert _core.Tracker.gate_for(c, 0.5) == pytest.approx(0.05)


def test_association_within_the_gate_and_new_tracks_beyond_it():
    tr = _core.Tracker(obb())
    a, b, c = (0.40, 0.0), (0.50, 0.0), (0.70, 0.0)
    tids = tr.update([est_at(a, seed=1), est_at(b, seed=2), est_at(c, seed=3)], [OBL] * 3, 0.0)
    assert tids == [0, 1, 2] and tr.last_gate == pytest.approx(0.05, abs=0.001)
    # A moved 3 cm (< gate), B stays, a new object D appears 20 cm from everything
    d = (0.40, 0.20)
    tids = tr.update([est_at((0.43, 0.0), seed=4), est_at(b, seed=5), est_at(d, seed=6)], [OBL] * 3, 0.1)
    assert tids[:2] == [0, 1] and tids[2] == 3
    assert [t.tid for t in tr.tracks] == [0, 1, 2, 3]  # sorted by tid
    # B jumps 8 cm while its neighbours define a 5 cm gate: a new track, not B
    tids = tr.update([est_at((0.43, 0.0), seed=7), est_at((0.58, 0.0), seed=8), est_at(d, seed=9)], [OBL] * 3, 0.2)
    assert tids == [0, 4, 3]


def test_single_observation_has_no_gate():
    tr = _core.Tracker(obb())
    tr.update([est_at((0.4, 0.0), seed=1), est_at((0.6, 0.0), seed=2)], [OBL, OBL], 0.0)
    tids = tr.update([est_at((0.9, 0.5), seed=3)], [OBL], 0.1)  # far, but no gate: nearest
    assert tr.last_gate is None and tids == [1]


def test_a_new_track_is_used_for_this_frame_too():
    tr = _core.Tracker(obb(assoc_gate_frac=2.0))  # a generous gate: 2 x min distance
    tr.update([est_at((0.2, 0.0), seed=1)], [OBL], 0.0)
    # X starts a new track (0.5 m from the only track); Y is 2 cm from X, inside the gate,
    # but X's new track is already used this frame -> Y gets its own
    tids = tr.update([est_at((0.70, 0.0), seed=2), est_at((0.72, 0.0), seed=3)], [OBL, OBL], 0.1)
    assert tids == [1, 2]


def test_nadir_observation_matching_nothing_starts_a_nadir_track():
    tr = _core.Tracker(obb())
    tr.update([est_at((0.4, 0.0), seed=1), est_at((0.6, 0.0), seed=2)], [OBL, OBL], 0.0)
    tids = tr.update([est_at((0.4, 0.0), seed=3), est_at((0.5, 0.3), seed=4)], [OBL, NAD], 0.1)
    assert tids == [0, 2]
    t2 = next(t for t in tr.tracks if t.tid == 2)
    assert t2.quality == NAD and t2.window_size == 1


def test_prior_theta_only_within_the_gate():
    tr = _core.Tracker(obb())
    tr.update([est_at((0.5, 0.0), yaw_deg=30.0, seed=1)], [OBL], 0.0)
    th = tr.tracks[0].smoothed.theta_rad
    assert tr.prior_theta([0.52, 0.0, 0.225], 0.05) == th
    assert tr.prior_theta([0.60, 0.0, 0.225], 0.05) is None
    assert tr.prior_theta([0.90, 0.0, 0.225], None) == th  # no gate: the nearest track


def test_new_object_does_not_borrow_a_neighbours_theta():
    tr = _core.Tracker(obb())
    pts_a = square((0.5, 0.0), yaw_deg=20.0, seed=1)
    e = estimate(pts_a, theta_prev=math.radians(110.0))  # the track settled on the 110° run
    tr.update([e], [OBL], 0.0)
    assert math.degrees(tr.tracks[0].smoothed.theta_rad) == pytest.approx(110.0, abs=2.0)
    pts_b = square((0.6, 0.0), yaw_deg=20.0, seed=2)  # a new square 10 cm away (gate 5 cm)
    ra, rb = _core.estimate_with_priors([square((0.5, 0.0), yaw_deg=20.0, seed=3), pts_b], TABLE, obb(), tr,
                                        band=0.01)
    assert math.degrees(ra.estimate.theta_rad) == pytest.approx(110.0, abs=2.0)  # its own prior
    assert math.degrees(rb.estimate.theta_rad) == pytest.approx(20.0, abs=2.0)  # no borrowed prior
    # alone in its frame (no gate), it WOULD take the nearest track's theta
    (rb1,) = _core.estimate_with_priors([pts_b], TABLE, obb(), tr, band=0.01)
    assert math.degrees(rb1.estimate.theta_rad) == pytest.approx(110.0, abs=2.0)


def test_estimate_with_priors_keeps_failures_in_place():
    tr = _core.Tracker(obb())
    line = np.column_stack([np.linspace(0.4, 0.45, 50), np.zeros(50), np.full(50, 0.25)])
    res = _core.estimate_with_priors([square((0.6, 0.0), seed=1), line], TABLE, obb(), tr, band=0.01)
    assert res[0].estimate is not None and res[1].estimate is None and "collinear" in res[1].failure


# --------------------------------------------------------------------------------------
# disambiguate, then smooth: the alternating 0°/90° sequence


def test_alternating_square_keeps_the_true_width_and_smooth_first_gives_the_diagonal():
    side = 0.05
    frames = [square((0.5, 0.0), yaw_deg=(1.0 if k % 2 == 0 else -1.0), side=side, seed=k, n=900)
              for k in range(10)]
    # the flip exists: without a prior the chosen run alternates between ~1° and ~89°
    raw = [estimate(p) for p in frames]
    raw_deg = [math.degrees(e.theta_rad) for e in raw]
    assert all(abs(d - 1.0) < 1.0 for d in raw_deg[0::2])
    assert all(abs(d - 89.0) < 1.0 for d in raw_deg[1::2])

    # the order of method.md §4: estimate -> prior from the track -> estimate again -> smooth
    tr = _core.Tracker(obb())
    for k, pts in enumerate(frames):
        (r,) = _core.estimate_with_priors([pts], TABLE, obb(), tr, band=0.01)
        tr.update([r.estimate], [OBL], 0.1 * k)
        (track,) = tr.tracks
        sm = track.smoothed
        assert _core.angle_dist_mod_pi(sm.theta_rad, 0.0) < math.radians(1.5)
        assert sm.width_m == pytest.approx(side, abs=0.001)
        # what the gripper really meets along the published closing axis
        assert true_extent(pts, sm.theta_rad) == pytest.approx(side, rel=0.03)
        assert np.allclose(sm.R_box[:, 0], [math.cos(sm.theta_rad), math.sin(sm.theta_rad), 0.0])

    # naive smooth-first: feed the raw (no-prior) estimates to the tracker
    naive = _core.Tracker(obb())
    diag = []
    for k, (pts, e) in enumerate(zip(frames, raw)):
        naive.update([e], [OBL], 0.1 * k)
        sm = naive.tracks[0].smoothed
        diag.append(true_extent(pts, sm.theta_rad) / side)
    # with an even window the circular median averages ~1° and ~89° into ~45°: the
    # diagonal, sqrt(2) - 1 = +41 % wider than the side
    # (sampled faces rarely reach their corners, hence a little under sqrt(2))
    assert 1.3 < diag[1] <= math.sqrt(2) + 0.01
    assert all(d > 1.3 for d in diag[1:6:2])  # frames 2, 4, 6: even windows


# --------------------------------------------------------------------------------------
# observe(): quality only goes up, windows, rebuilt fields


def test_oblique_after_nadir_never_overwrites():
    tr = _core.Tracker(obb())
    tr.update([est_at((0.5, 0.0), seed=1)], [NAD], 0.0)
    before = tr.tracks[0].smoothed
    wide = estimate(square((0.5, 0.0), size=(0.07, 0.04), seed=2))
    tids = tr.update([wide], [OBL], 1.0)
    (t,) = tr.tracks
    assert tids == [0] and t.quality == NAD and t.last_seen_s == 1.0  # last_seen refreshed
    assert t.smoothed.width_m == before.width_m and np.array_equal(t.smoothed.center, before.center)
    assert t.window_size == 1


def test_windows_restart_when_quality_rises():
    tr = _core.Tracker(obb())
    for k in range(3):
        tr.update([estimate(square((0.5, 0.0), size=(0.04, 0.07), seed=k))], [OBL], 0.1 * k)
    assert tr.tracks[0].window_size == 3
    assert tr.tracks[0].smoothed.width_m == pytest.approx(0.04, abs=0.001)
    nadir = estimate(square((0.5, 0.0), side=0.05, seed=9))
    tr.update([nadir], [NAD], 1.0)
    (t,) = tr.tracks
    assert t.quality == NAD and t.window_size == 1
    assert t.smoothed.width_m == nadir.width_m  # not a median over oblique samples
    assert np.array_equal(t.smoothed.center, nadir.center)


def test_window_length_and_medians():
    tr = _core.Tracker(obb())
    widths = [0.030, 0.034, 0.031, 0.036, 0.032, 0.038, 0.033, 0.039, 0.035]
    ests = [estimate(square((0.5, 0.0), size=(w, 0.07), yaw_deg=0.0, seed=k)) for k, w in enumerate(widths)]
    got = []
    for k, e in enumerate(ests):
        tr.update([e], [OBL], 0.1 * k)
        got.append(tr.tracks[0].smoothed.width_m)
    w = [e.width_m for e in ests]
    assert got[1] == pytest.approx((w[0] + w[1]) / 2)  # even count: mean of the two middle
    assert got[2] == pytest.approx(np.median(w[:3]))
    assert got[8] == pytest.approx(np.median(w[2:9]))  # the last 7 only
    assert tr.tracks[0].window_size == 7
    heights = [e.height_m for e in ests]
    assert tr.tracks[0].smoothed.height_m == pytest.approx(np.median(heights[2:9]))
    cx = [e.center[0] for e in ests]
    assert tr.tracks[0].smoothed.center[0] == pytest.approx(np.median(cx[2:9]))


def test_smoothed_fields_are_rebuilt_and_per_frame_fields_come_from_the_frame():
    tr = _core.Tracker(obb())
    e1 = estimate(square((0.5, 0.0), size=(0.07, 0.03), yaw_deg=10.0, seed=1))
    e2 = estimate(square((0.5, 0.0), size=(0.07, 0.03), yaw_deg=12.0, seed=2))
    e3 = estimate(square((0.5, 0.0), size=(0.09, 0.12), yaw_deg=14.0, seed=3, n=400))
    assert not e3.width_ok
    for k, e in enumerate((e1, e2, e3)):
        tr.update([e], [OBL], 0.1 * k)
    sm = tr.tracks[0].smoothed
    assert sm.width_m == pytest.approx(np.median([e1.width_m, e2.width_m, e3.width_m]))
    assert sm.width_m < 0.035
    assert sm.width_ok and sm.grasp_ok and sm.notes == []  # guards from the smoothed width
    th = sm.theta_rad
    assert np.allclose(sm.R_box[:, 0], [math.cos(th), math.sin(th), 0])
    assert np.allclose(sm.R_box[:, 1], [-math.sin(th), math.cos(th), 0])
    assert np.linalg.det(sm.R_box) == pytest.approx(1.0)
    assert np.allclose(sm.extents, [sm.width_m, sm.perp_width_m, sm.height_m])
    assert sm.yaw_defined == (sm.anisotropy >= 1.10)
    assert sm.num_points == e3.num_points and sm.pca_tilt_deg == e3.pca_tilt_deg  # this frame's


# --------------------------------------------------------------------------------------
# retirement


def test_two_level_retirement_and_tids_never_reused():
    tr = _core.Tracker(obb())
    tr.update([est_at((0.4, 0.0), seed=1), est_at((0.6, 0.0), seed=2)], [OBL, NAD], 10.0)
    tr.retire(12.0)  # age 2.0: not above max_age_s
    assert [t.tid for t in tr.tracks] == [0, 1]
    tr.retire(12.01)  # OBLIQUE track gone, NADIR held
    assert [t.tid for t in tr.tracks] == [1]
    tr.retire(20.0)
    assert [t.tid for t in tr.tracks] == [1]
    tr.retire(20.01)
    assert tr.tracks == []
    tids = tr.update([est_at((0.4, 0.0), seed=3)], [OBL], 21.0)
    assert tids == [2]  # a new id, never a retired one
    tr.reset()
    assert tr.tracks == [] and tr.last_gate is None
    assert tr.update([est_at((0.4, 0.0), seed=4)], [OBL], 22.0) == [3]


def test_an_oblique_observation_keeps_a_nadir_track_alive():
    tr = _core.Tracker(obb())
    tr.update([est_at((0.5, 0.0), seed=1)], [NAD], 0.0)
    tr.update([est_at((0.5, 0.0), seed=2)], [OBL], 9.0)
    tr.retire(18.0)
    assert len(tr.tracks) == 1 and tr.tracks[0].quality == NAD
