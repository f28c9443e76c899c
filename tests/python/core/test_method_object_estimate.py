"""method.md §2 (object estimate of one cluster) through the bindings.

2.1 decomposition, 2.2 width scan and anisotropy, 2.3 closing direction (runs, wrap-around
merge, prior), 2.4 box / slice-median height / centre, 2.5 PCA (diagnostic), 2.6 guards.
"""

import math
import re

import numpy as np
import pytest

import synthetic_clouds as sc
from grasp_pipeline import _core

PI = math.pi
TABLE = _core.Plane([0, 0, 1], -0.2)


def obb(**kw):
    p = _core.ObbParams()
    for k, v in kw.items():
        setattr(p, k, v)
    return p


def est(points, plane=TABLE, theta_prev=None, band=0.01, **kw):
    res = _core.estimate_object(points, plane, obb(**kw), theta_prev=theta_prev, band=band)
    assert res.estimate is not None, res.failure
    assert res.failure == ""
    return res.estimate


def rot(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


def test_obb_defaults_are_the_spec_table():
    p = _core.ObbParams()
    assert p.depth_noise_sigma == 0.002 and p.top_slice_sigmas == 4.0 and p.top_slice_iters == 3
    assert p.n_theta == 361 and p.width_tol_m == 0.002 and p.isotropy_ratio_max == 1.10
    assert p.gripper_open == 0.08 and p.min_graspable_width == 0.005 and p.min_height == 0.005
    assert p.resting_margin == 0.008 and p.window == 7 and p.assoc_gate_frac == 0.5
    assert p.max_age_s == 2.0 and p.nadir_hold_s == 10.0 and p.nadir_angle_max_deg == 5.0


# --------------------------------------------------------------------------------------
# 2.1 decomposition


@pytest.mark.parametrize("n", [[0, 0, 1], [0.1, -0.05, 1], [0.95, 0.0, 0.3], [0.0, 0.99, 0.1]])
def test_in_plane_basis_is_orthonormal_right_handed_and_deterministic(n):
    u, v = _core.in_plane_basis(n)
    nn = np.asarray(n, float) / np.linalg.norm(n)
    assert abs(np.dot(u, nn)) < 1e-12 and abs(np.dot(v, nn)) < 1e-12 and abs(np.dot(u, v)) < 1e-12
    assert np.allclose(np.cross(u, v), nn, atol=1e-12)
    u2, v2 = _core.in_plane_basis(n)
    assert np.array_equal(u, u2) and np.array_equal(v, v2)


def test_basis_for_a_level_table_is_world_x_y():
    u, v = _core.in_plane_basis([0, 0, 1])
    assert np.allclose(u, [1, 0, 0]) and np.allclose(v, [0, 1, 0])


def test_estimate_is_expressed_in_the_plane_for_a_tilted_table():
    # the same object on a level table and on a table tilted 7° about a skew axis, with the
    # whole scene rotated about a point: the box is the same, moved rigidly
    cube = sc.box_surface((0.5, 0.1), (0.03, 0.06, 0.04), yaw_rad=0.4, sides=(0, 1), seed=2)
    level = est(cube)
    R = rot([1.0, 0.4, 0.0], math.radians(7.0))
    pivot = np.array([0.2, -0.1, 0.2])
    moved = (cube - pivot) @ R.T + pivot
    n = R @ np.array([0, 0, 1.0])
    tilted_plane = _core.Plane(n, -float(n @ pivot))
    tilted = est(moved, plane=tilted_plane)
    assert tilted.width_m == pytest.approx(level.width_m, abs=1e-4)
    assert tilted.perp_width_m == pytest.approx(level.perp_width_m, abs=1e-4)
    assert tilted.height_m == pytest.approx(level.height_m, abs=1e-4)
    assert np.allclose(tilted.center, (level.center - pivot) @ R.T + pivot, atol=2e-4)
    assert np.allclose(tilted.R_box[:, 2], n, atol=1e-12)  # third axis = the plane normal
    # closing axis: the same physical direction (up to sign)
    assert abs(abs(tilted.R_box[:, 0] @ (R @ level.R_box[:, 0])) - 1) < 1e-4


# --------------------------------------------------------------------------------------
# 2.2 width scan and anisotropy


def test_scan_angles_exclude_pi():
    T = 361
    assert _core.scan_angle_rad(0, T) == 0.0
    assert _core.scan_angle_rad(180, T) == pytest.approx(PI * 180 / 361)
    assert _core.scan_angle_rad(T - 1, T) == pytest.approx(PI * 360 / 361) and _core.scan_angle_rad(T - 1, T) < PI


def test_width_scan_is_max_minus_min_of_the_projection():
    r = np.random.default_rng(0)
    a = r.uniform(-0.015, 0.015, 500)
    b = r.uniform(-0.035, 0.035, 500)
    ext = np.asarray(_core.width_scan(list(a), list(b), 12))
    assert len(ext) == 12
    for t in range(12):
        th = PI * t / 12
        proj = a * math.cos(th) + b * math.sin(th)
        assert ext[t] == pytest.approx(proj.max() - proj.min(), abs=1e-12)
        assert _core.extent_along(list(a), list(b), th) == pytest.approx(ext[t], abs=1e-12)
    assert _core.anisotropy_ratio(list(ext)) == pytest.approx(ext.max() / ext.min())
    assert _core.anisotropy_ratio([0.0, 0.05]) == math.inf


def test_square_is_yaw_defined_and_round_is_not():
    sq = est(sc.box_top((0.5, 0.0), (0.05, 0.05), 0.25, yaw_rad=math.radians(20)))
    # measured 1.28–1.38 on partial views; a complete square is sqrt(2)
    assert 1.28 <= sq.anisotropy <= 1.42 and sq.yaw_defined
    disc = est(sc.disc_top((0.5, 0.0), 0.05, 0.26))
    assert 1.0 <= disc.anisotropy <= 1.04 and not disc.yaw_defined  # measured 1.004–1.04
    assert disc.width_m == pytest.approx(0.05, abs=0.0015)


# --------------------------------------------------------------------------------------
# 2.3 closing direction


def test_runs_merge_across_the_wrap_and_take_the_circular_median():
    T = 12
    ext = [0.05] * T
    for t in (0, 1, 11):  # one run across the ends of the scan
        ext[t] = 0.030
    ext[5], ext[6] = 0.031, 0.0305  # a second run
    runs = _core.direction_runs(ext, 0.002)
    assert len(runs) == 2
    merged = next(r for r in runs if 0 in r.indices)
    assert sorted(merged.indices) == [0, 1, 11]
    assert merged.indices == [11, 0, 1]  # circular order
    assert merged.first == 11 and merged.last == 1
    assert _core.angle_dist_mod_pi(merged.theta_rad, 0.0) < 1e-12  # centre of {-15°, 0°, 15°}
    assert merged.width_m == 0.030
    other = next(r for r in runs if 5 in r.indices)
    assert other.theta_rad == pytest.approx(5.5 * PI / 12)  # even count: mean of the two middle
    assert other.width_m == 0.0305
    # an even merged run: centre between 165° and 180°
    ext2 = [0.05] * T
    ext2[0] = ext2[11] = 0.03
    (run,) = _core.direction_runs(ext2, 0.002)
    assert run.theta_rad == pytest.approx(23 * PI / 24)


def test_choice_without_prior_is_the_smallest_theta_and_with_prior_the_nearest_run():
    T = 12
    ext = [0.05] * T
    ext[3] = 0.0315  # 45°, a bit wider but within tolerance of the smallest
    ext[8] = 0.0300  # 120°
    c = _core.choose_direction(ext, 0.002, None)
    assert len(c.runs) == 2 and c.theta_rad == pytest.approx(3 * PI / 12) and c.width_m == 0.0315
    c = _core.choose_direction(ext, 0.002, 2.0)
    assert c.theta_rad == pytest.approx(8 * PI / 12) and c.runs[c.chosen].width_m == 0.03
    # distance is mod pi: a prior of 179° is nearest to the 45° run? no: to 120° (59°) vs 45° (46°)
    c = _core.choose_direction(ext, 0.002, math.radians(179.0))
    assert c.theta_rad == pytest.approx(3 * PI / 12)
    c = _core.choose_direction(ext, 0.002, math.radians(-40.0))  # -40° == 140°: 20° from 120°
    assert c.theta_rad == pytest.approx(8 * PI / 12)


def test_square_has_two_equivalent_runs_and_the_prior_picks_the_near_one():
    pts = sc.box_top((0.5, 0.0), (0.05, 0.05), 0.25, yaw_rad=math.radians(20), seed=1)
    a, b = list(pts[:, 0] - 0.5), list(pts[:, 1])
    runs = _core.direction_runs(_core.width_scan(a, b, 361), 0.002)
    assert len(runs) == 2
    thetas = sorted(math.degrees(r.theta_rad) for r in runs)
    assert thetas[0] == pytest.approx(20.0, abs=1.0) and thetas[1] == pytest.approx(110.0, abs=1.0)
    no_prior = est(pts)
    assert math.degrees(no_prior.theta_rad) == pytest.approx(thetas[0], abs=1e-9)  # smallest theta
    near_110 = est(pts, theta_prev=math.radians(100.0))
    assert math.degrees(near_110.theta_rad) == pytest.approx(thetas[1], abs=1e-9)
    for e in (no_prior, near_110):
        assert e.width_m == pytest.approx(0.05, abs=0.001)


def test_axis_aligned_square_merges_the_run_across_zero():
    pts = sc.box_top((0.5, 0.0), (0.05, 0.05), 0.25, yaw_rad=0.0, seed=2)
    runs = _core.direction_runs(_core.width_scan(list(pts[:, 0] - 0.5), list(pts[:, 1]), 361), 0.002)
    assert len(runs) == 2
    wrap = next(r for r in runs if 0 in r.indices)
    assert 360 in wrap.indices and wrap.last < wrap.first
    assert _core.angle_dist_mod_pi(wrap.theta_rad, 0.0) < math.radians(1.0)  # not 90°
    e = est(pts, theta_prev=math.radians(178.0))
    assert _core.angle_dist_mod_pi(e.theta_rad, 0.0) < math.radians(1.0)
    assert e.width_m == pytest.approx(0.05, abs=0.001)


def test_rectangle_closes_across_its_short_side():
    e = est(sc.box_surface((0.5, 0.0), (0.07, 0.03, 0.04), yaw_rad=math.radians(30), sides=(0, 1), seed=3))
    assert _core.angle_dist_mod_pi(e.theta_rad, math.radians(120.0)) < math.radians(1.5)
    assert e.width_m == pytest.approx(0.03, abs=0.0015)
    assert e.perp_width_m == pytest.approx(0.07, abs=0.0015)
    assert e.yaw_defined and e.anisotropy >= 1.1


def test_angle_helpers():
    assert _core.wrap_mod_pi(-0.1) == pytest.approx(PI - 0.1)
    assert _core.wrap_mod_pi(PI) == pytest.approx(0.0)
    assert _core.angle_dist_mod_pi(0.1, PI - 0.1) == pytest.approx(0.2)
    assert _core.angle_dist_mod_pi(0.0, PI / 2) == pytest.approx(PI / 2)
    assert _core.angle_dist_mod_pi(3.0, 3.0 + 5 * PI) == pytest.approx(0.0, abs=1e-9)
    m = _core.circular_median_mod_pi([PI - 0.01, 0.01], PI - 0.01)
    assert _core.angle_dist_mod_pi(m, 0.0) < 1e-12
    # order does not matter
    m1 = _core.circular_median_mod_pi([3.10, 0.02, 0.05, 3.12], 3.10)
    m2 = _core.circular_median_mod_pi([0.05, 3.12, 3.10, 0.02], 0.05)
    assert _core.angle_dist_mod_pi(m1, m2) < 1e-12
    assert _core.median([1.0, 2.0, 3.0, 4.0]) == 2.5
    assert _core.median([3.0, 1.0, 2.0]) == 2.0
    assert math.isnan(_core.median([]))


# --------------------------------------------------------------------------------------
# 2.4 box, height, centre


def test_box_axes_extents_and_centre():
    yaw = math.radians(30)
    e = est(sc.box_surface((0.5, 0.1), (0.07, 0.03, 0.04), yaw_rad=yaw, sides=(0, 1, 2, 3), seed=4))
    th = e.theta_rad
    u, v = _core.in_plane_basis([0, 0, 1])
    e_th = math.cos(th) * u + math.sin(th) * v
    e_perp = -math.sin(th) * u + math.cos(th) * v
    assert np.allclose(e.R_box[:, 0], e_th) and np.allclose(e.R_box[:, 1], e_perp)
    assert np.allclose(e.R_box[:, 2], [0, 0, 1])
    assert np.linalg.det(e.R_box) == pytest.approx(1.0, abs=1e-12)
    assert np.allclose(e.extents, [e.width_m, e.perp_width_m, e.height_m])
    # (side points near the top fall into the 8 mm slice and pull the median down a little)
    assert e.height_m == pytest.approx(0.04, abs=0.001)
    assert np.allclose(e.center, [0.5, 0.1, 0.2 + e.height_m / 2], atol=0.001)
    assert e.theta_deg == pytest.approx(math.degrees(th))


def test_centre_is_the_box_midpoint_not_the_centroid():
    r = np.random.default_rng(5)
    dense = sc.box_top((0.49, 0.0), (0.03, 0.05), 0.25, n=3000, seed=5)  # left part crowded
    sparse = sc.box_top((0.52, 0.0), (0.03, 0.05), 0.25, n=200, seed=6)
    pts = np.vstack([dense, sparse])
    e = est(pts)
    assert pts[:, 0].mean() < 0.495
    assert e.center[0] == pytest.approx(0.505, abs=0.001) and e.center[1] == pytest.approx(0.0, abs=0.001)
    assert e.center[2] == pytest.approx(0.2 + e.height_m / 2, abs=1e-12)
    del r


def test_slice_median_height_versus_max_bias():
    pts = sc.box_top((0.5, 0.0), (0.05, 0.05), 0.25, n=2500, sigma=0.002, seed=7)
    e = est(pts)
    d_max = pts[:, 2].max() - 0.2
    assert d_max - 0.05 > 0.005  # the max sits > 2.5 sigma too high (extreme value)
    assert abs(e.height_m - 0.05) < 0.0005
    # averaging does not remove the max's bias: the mean of the per-cloud maxima stays high
    maxima = [sc.box_top((0.5, 0.0), (0.05, 0.05), 0.25, n=2500, seed=s)[:, 2].max() - 0.2 for s in range(5)]
    assert np.mean(maxima) - 0.05 > 0.005


def test_slice_median_top_algorithm():
    # top = max; keep d >= top - k sigma; top = median(kept); until unchanged / < 3 kept
    d = [0.0, 0.01, 0.02, 0.03, 0.04]
    assert _core.slice_median_top(d, 0.005, 4.0, 1) == pytest.approx(0.03)
    assert _core.slice_median_top(d, 0.005, 4.0, 2) == pytest.approx(0.025)
    assert _core.slice_median_top(d, 0.005, 4.0, 3) == pytest.approx(0.025)
    assert _core.slice_median_top(d, 0.0025, 4.0, 3) == pytest.approx(0.04)  # only 2 kept: stop
    assert _core.slice_median_top([0.048, 0.050, 0.052, 0.054], 0.002, 4.0, 3) == pytest.approx(0.051)


def test_horizontal_spans_stay_max_minus_min():
    e = est(sc.box_top((0.5, 0.0), (0.05, 0.04), 0.25, yaw_rad=0.2, n=4000, seed=8))
    # a dense sample of the face: the span is within 1 % of the side (measured bias 0.6 %)
    assert abs(e.width_m - 0.04) / 0.04 < 0.01 and abs(e.perp_width_m - 0.05) / 0.05 < 0.01


# --------------------------------------------------------------------------------------
# 2.5 PCA (diagnostic)


def test_pca_fails_on_too_few_coincident_and_collinear_points():
    assert _core.pca_box(np.zeros((2, 3))) is None
    assert "fewer than 3" in _core.pca_box_failure(np.zeros((2, 3)))
    same = np.tile([0.5, 0.25, 0.125], (10, 1))  # exactly representable: lambda1 == 0
    assert _core.pca_box(same) is None and "coincide" in _core.pca_box_failure(same)
    assert _core.pca_box(np.tile([0.1, 0.2, 0.3], (10, 1))) is None
    line = np.column_stack([np.linspace(0, 0.05, 50), np.linspace(0, 0.02, 50), np.full(50, 0.2)])
    assert _core.pca_box(line) is None and "collinear" in _core.pca_box_failure(line)
    # the estimate fails with it (no estimate for that cluster)
    res = _core.estimate_object(line, TABLE, obb(), band=0.01)
    assert res.estimate is None and "collinear" in res.failure


def test_pca_succeeds_on_coplanar_points_with_det_plus_one():
    top = sc.box_top((0.5, 0.0), (0.05, 0.03), 0.25, sigma=0.0, seed=9)
    box = _core.pca_box(top)
    assert box is not None and _core.pca_box_failure(top) == ""
    assert box.eigenvalues[2] == pytest.approx(0.0, abs=1e-15)
    assert np.linalg.det(box.R) == pytest.approx(1.0, abs=1e-12)
    assert _core.pca_tilt_deg(box, [0, 0, 1]) == pytest.approx(0.0, abs=1e-6)
    r = np.random.default_rng(10)
    for _ in range(20):
        pts = r.normal(size=(30, 3)) * r.uniform(0.01, 1.0, 3)
        b = _core.pca_box(pts)
        assert np.linalg.det(b.R) == pytest.approx(1.0, abs=1e-9)
        assert np.allclose(b.R.T @ b.R, np.eye(3), atol=1e-9)
        assert b.eigenvalues[0] >= b.eigenvalues[1] >= b.eigenvalues[2]


def test_pca_covariance_box_and_centre():
    r = np.random.default_rng(11)
    pts = np.vstack([r.normal(size=(200, 3)) * [0.03, 0.01, 0.002], [[0.2, 0.0, 0.0]]])  # one far point
    b = _core.pca_box(pts)
    evals = np.sort(np.linalg.eigvalsh(np.cov(pts.T, ddof=1)))[::-1]
    assert np.allclose(b.eigenvalues, evals, rtol=1e-9)
    proj = (pts - pts.mean(axis=0)) @ b.R
    lo, hi = proj.min(axis=0), proj.max(axis=0)
    assert np.allclose(b.extents, hi - lo)
    assert np.allclose(b.center, pts.mean(axis=0) + b.R @ ((lo + hi) / 2))
    assert np.linalg.norm(b.center - pts.mean(axis=0)) > 0.01  # not the centroid


def test_pca_tilt_is_a_diagnostic_only():
    # an oblique view (top + two sides) tilts the PCA box; the width scan does not care
    e = est(sc.box_surface((0.5, 0.0), (0.05, 0.05, 0.05), yaw_rad=0.3, sides=(0, 1), seed=12))
    assert e.pca_tilt_deg > 10.0
    assert e.width_m == pytest.approx(0.05, abs=0.0015)
    assert np.allclose(e.R_box[:, 2], [0, 0, 1])
    top = est(sc.box_top((0.5, 0.0), (0.05, 0.05), 0.25, seed=12))
    assert top.pca_tilt_deg < 1.0


# --------------------------------------------------------------------------------------
# 2.6 guards


def test_resting_cube_with_sides_is_graspable_without_notes():
    e = est(sc.box_surface((0.5, 0.0), (0.05, 0.05, 0.05), yaw_rad=0.3, sides=(0, 1), seed=13))
    assert e.resting and e.height_ok and e.width_ok and e.grasp_ok
    assert e.notes == [] and e.undetermined_notes == [] and e.resting_note == ""
    assert e.lowest_m == pytest.approx(0.0, abs=0.002)


def test_floating_object_is_refused_with_a_note():
    e = est(sc.box_surface((0.5, 0.0), (0.05, 0.05, 0.05), base_z=0.23, yaw_rad=0.3, sides=(0, 1), seed=14))
    assert not e.resting and not e.grasp_ok and e.height_ok and e.width_ok
    assert e.resting_note.startswith("floating/stacked: lowest point 30.0 mm above plane")
    assert "(band + margin = 18.0 mm)" in e.resting_note
    assert e.notes == [e.resting_note]
    # just within band + margin (1.5 cm above the plane): resting
    e2 = est(sc.box_surface((0.5, 0.0), (0.05, 0.05, 0.05), base_z=0.215, yaw_rad=0.3, sides=(0, 1), seed=14))
    assert e2.resting and e2.grasp_ok


def test_top_only_is_undetermined_and_never_refused():
    e = est(sc.box_top((0.5, 0.0), (0.05, 0.05), 0.28, seed=15))  # 8 cm up, only the top seen
    assert e.resting and e.grasp_ok and e.notes == []
    assert len(e.undetermined_notes) == 1 and "only the top" in e.undetermined_notes[0]
    e = est(sc.box_surface((0.5, 0.0), (0.05, 0.05, 0.05), base_z=0.23, sides=(0, 1), seed=16), band=None)
    assert e.resting and e.grasp_ok and e.notes == []
    assert any("band unknown" in s for s in e.undetermined_notes)


def test_too_low_object():
    e = est(sc.box_top((0.5, 0.0), (0.05, 0.05), 0.203, seed=17))
    assert not e.height_ok and not e.grasp_ok and e.resting and e.width_ok
    (note,) = e.notes
    m = re.fullmatch(r"too low: (\d+\.\d) mm \(min 5\.0 mm\)", note)
    assert m and abs(float(m.group(1)) - 3.0) <= 0.3
    assert float(m.group(1)) == round(e.height_m * 1000, 1)


@pytest.mark.parametrize("kind, width", [("wide", 0.10), ("fin", 0.003)])
def test_width_not_graspable(kind, width):
    if kind == "wide":
        pts = sc.box_surface((0.5, 0.0), (0.10, 0.12, 0.05), sides=(0, 1, 2, 3), n_top=3000, seed=18)
    else:  # a 3 mm fin seen from above
        pts = sc.box_top((0.5, 0.0), (0.003, 0.05), 0.25, seed=18)
    e = est(pts)
    assert e.width_m == pytest.approx(width, abs=0.0015)
    assert not e.width_ok and not e.grasp_ok and e.resting and e.height_ok
    (note,) = e.notes
    m = re.fullmatch(r"width not graspable: (\d+\.\d) mm \(5\.0–80\.0 mm\)", note)
    assert m and float(m.group(1)) == round(e.width_m * 1000, 1)


def test_hard_notes_are_ordered_resting_first():
    e = est(sc.box_surface((0.5, 0.0), (0.10, 0.12, 0.05), base_z=0.24, sides=(0, 1), seed=19))
    assert not e.grasp_ok and len(e.notes) == 2
    assert e.notes[0].startswith("floating/stacked") and e.notes[1].startswith("width not graspable")


def test_guard_limits_are_inclusive_and_follow_the_parameters():
    pts = sc.box_surface((0.5, 0.0), (0.04, 0.06, 0.05), yaw_rad=0.0, sides=(0, 1, 2, 3), seed=20)
    base = est(pts)
    e = est(pts, gripper_open=base.width_m)
    assert e.width_ok
    e = est(pts, gripper_open=base.width_m - 1e-4)
    assert not e.width_ok
    e = est(pts, min_height=base.height_m + 1e-4)
    assert not e.height_ok and e.notes[0].startswith("too low")
