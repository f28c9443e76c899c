"""Grasps fitted to the points (orchestration/grasping/fit.py) on small synthetic clouds."""

from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest

from grasp_pipeline.motion.occupancy import OrientedBox
from grasp_pipeline.orchestration.config import GraspConfig, GraspFitConfig
from grasp_pipeline.orchestration.grasping.fit import (FittedLine, LineLimits, Neighbours,
                                                       box_grasp_blocked, box_samples, check_line,
                                                       fit_lines, rank_lines)
from grasp_pipeline.orchestration.grasping.opening import max_grasp_width_m
from grasp_pipeline.orchestration.grasping.source import GraspRequest
from grasp_pipeline.orchestration.grasping.top_down import GeometricGraspSource, planner_hand_spheres
from grasp_pipeline.motion.perceived_scene import PerceivedScene
from grasp_pipeline.robot.description import HandClearances

from ..clouds import ENV, UP, block, scene, table, track_of

HAND = HandClearances(pad_below_tcp_m=0.011, palm_above_tcp_m=0.0394, finger_thickness_m=0.02,
                      finger_width_m=0.019)
CFG = GraspFitConfig()
GRASP = GraspConfig()
MAX_WIDTH = max_grasp_width_m(CFG)  # the usable opening, 72 mm


def _fit(track, cloud, boxes=(), spheres=None):
    lines = fit_lines(track, cloud, HAND, GRASP, CFG, 0.005, MAX_WIDTH, Neighbours(tuple(boxes)), 0.005, spheres)
    return lines, rank_lines(lines, CFG)


def _l_block():
    """An L: a 60 x 20 mm arm along x and a 20 x 60 mm arm along y, 40 mm tall."""
    return np.vstack([block(0.50, 0.56, 0.00, 0.02, 0.0, 0.04), block(0.50, 0.52, 0.00, 0.06, 0.0, 0.04)])


def _on_material(pts, position, closing, half_len):
    """Points of ``pts`` on the closing line through ``position`` (within ``half_len``)."""
    d = pts[:, :2] - position[:2]
    along = d @ closing[:2]
    across = np.abs(d @ np.array([-closing[1], closing[0]]))
    return np.count_nonzero((across <= 0.004) & (np.abs(along) <= half_len))


def test_an_l_block_is_grasped_on_its_material_not_at_the_box_centre():
    L = _l_block()
    cloud = scene((0, L), (ENV, table(holes=[(0.5, 0.56, 0.0, 0.06)])))
    lines, ranked = _fit(track_of(0, L), cloud)
    assert ranked, [ln.reason for ln in lines]
    box_centre = np.array([0.53, 0.03])
    assert _on_material(L, np.r_[box_centre, 0], np.array([1.0, 0, 0]), 0.005) == 0  # centre: air
    for ln in ranked:
        assert _on_material(L, ln.position, ln.closing, 0.5 * ln.width_m) >= 3, ln
        assert min(abs(ln.width_m - 0.02), abs(ln.width_m - 0.06)) < 0.004  # across or along one arm
    # a line through the empty quadrant is refused for want of material
    assert any(ln.reason.startswith("no material") or "edge" in ln.reason for ln in lines if not ln.ok)


def test_a_neighbour_in_a_finger_column_blocks_that_line_and_the_other_axis_is_used():
    cube = block(0.50, 0.54, 0.00, 0.04, 0.0, 0.04)
    wall = block(0.555, 0.565, -0.03, 0.07, 0.0, 0.05)  # a thin neighbour 15 mm right of it
    wall2 = block(0.475, 0.485, -0.03, 0.07, 0.0, 0.05)  # and one 15 mm left of it
    cloud = scene((0, cube), (1, wall), (2, wall2), (ENV, table()))
    lines, ranked = _fit(track_of(0, cube), cloud)
    assert ranked and all(ln.axis == 1 for ln in ranked)  # closing along y, away from the walls
    assert any(not ln.ok and "finger blocked" in ln.reason for ln in lines if ln.axis == 0)


def test_an_object_wider_than_the_opening_in_both_directions_has_no_line():
    slab = block(0.45, 0.55, 0.0, 0.09, 0.0, 0.03)
    lines, ranked = _fit(track_of(0, slab), scene((0, slab), (ENV, table())))
    assert not ranked and any("too wide" in ln.reason for ln in lines)


def test_the_table_band_does_not_block_the_fingers_but_points_above_it_do():
    cube = block(0.50, 0.54, 0.00, 0.04, 0.0, 0.04)
    noisy_table = table() + np.array([0, 0, 0.004])  # 4 mm high noise: still the table
    _, ranked = _fit(track_of(0, cube), scene((0, cube), (ENV, noisy_table)))
    assert ranked
    clutter = table() + np.array([0, 0, 0.02])  # unknown environment 20 mm up: blocks
    lines, ranked = _fit(track_of(0, cube), scene((0, cube), (ENV, clutter)))
    assert not ranked and all("blocked" in ln.reason or not ln.ok for ln in lines)


def test_a_mug_is_grasped_across_its_body_not_its_handle():
    th = np.linspace(0, 2 * np.pi, 180, endpoint=False)
    body = np.vstack([np.column_stack([0.5 + r * np.cos(th), r * np.sin(th), np.full(th.size, 0.09)])
                      for r in np.arange(0.0, 0.0341, 0.003)])
    handle = block(0.534, 0.56, -0.006, 0.006, 0.03, 0.07)
    mug = np.vstack([body, handle])
    cloud = scene((0, mug), (ENV, table(holes=[(0.46, 0.565, -0.04, 0.04)])))
    lines, ranked = _fit(track_of(0, mug), cloud)
    assert ranked
    best = ranked[0]
    assert abs(best.width_m - 0.068) < 0.006  # the body's diameter
    assert abs(best.closing[1]) > 0.99  # closing along y: the handle (along +x) stays out of the pads
    assert np.hypot(best.position[0] - 0.5, best.position[1]) < 0.01


def test_the_top_box_of_a_stack_is_grasped_on_itself_above_the_lower_box():
    lower = block(0.48, 0.58, -0.03, 0.07, 0.0, 0.04)
    upper = block(0.51, 0.55, 0.0, 0.04, 0.04, 0.08)
    cloud = scene((0, upper), (1, lower), (ENV, table()))
    _, ranked = _fit(track_of(0, upper), cloud)
    assert ranked
    for ln in ranked:
        pad_bottom = ln.position[2] - HAND.pad_below_tcp_m
        assert pad_bottom > 0.04  # above the lower box's top
        assert abs(ln.width_m - 0.04) < 0.004


def test_a_neighbour_box_under_the_hand_raises_the_grasp_or_refuses_it():
    spheres = planner_hand_spheres(0.04)
    cube = block(0.50, 0.54, 0.00, 0.04, 0.0, 0.06)
    cloud = scene((0, cube), (ENV, table()))
    tall = OrientedBox(np.array([0.52, 0.10, 0.04]), np.eye(3), np.array([0.04, 0.04, 0.08]))
    lines, ranked = _fit(track_of(0, cube), cloud, (tall,), spheres)
    free, _ = _fit(track_of(0, cube), cloud, (), spheres)
    assert free and ranked
    assert min(ln.position[2] for ln in free) < min(ln.position[2] for ln in ranked) or \
        all(ln.axis == 0 for ln in ranked)  # raised, or closing away from the tall box
    towering = OrientedBox(np.array([0.52, 0.09, 0.10]), np.eye(3), np.array([0.06, 0.06, 0.20]))
    lines, ranked = _fit(track_of(0, cube), cloud, (towering,), spheres)
    assert all(ln.axis == 0 for ln in ranked)
    assert any("meets a neighbour" in ln.reason for ln in lines if ln.axis == 1)


def test_unsegmented_environment_points_under_the_hand_count_like_a_neighbour_box():
    """A pile's unsegmented part (environment points 20 cm high beside the cube) blocks the
    hand as the planner's occupancy map does; the same points inside the target's cleared
    padding do not (the planner ignores them in the final approach)."""
    spheres = planner_hand_spheres(0.04)
    cube = block(0.50, 0.54, 0.00, 0.04, 0.0, 0.06)
    heap = block(0.49, 0.55, 0.085, 0.145, 0.0, 0.20, sides=False)
    cloud = scene((0, cube), (ENV, table()), (ENV, heap))
    grid = (0.005 + 0.0043, 0.005, 0.05)

    def fit(grid_):
        lines = fit_lines(track_of(0, cube), cloud, HAND, GRASP, CFG, 0.005, MAX_WIDTH, (), 0.005,
                          spheres, grid_)
        return lines, rank_lines(lines, CFG)

    lines, ranked = fit(grid)
    assert all(ln.axis == 0 for ln in ranked)
    assert any("neighbour" in ln.reason for ln in lines if ln.axis == 1)
    _, ranked_cleared = fit((grid[0], grid[1], 0.2))  # the heap inside the cleared padding
    assert any(ln.axis == 1 for ln in ranked_cleared)


def test_box_samples_cover_the_grown_top_face():
    b = OrientedBox(np.array([0.5, 0.0, 0.02]), np.eye(3), np.array([0.04, 0.02, 0.04]))
    s = box_samples([b], UP, 0.0, 0.005, 0.003)
    assert np.allclose(s[:, 2], 0.04)
    # the grown face's edges are sampled exactly; samples at most 3 mm apart
    assert s[:, 0].min() == pytest.approx(0.475) and s[:, 0].max() == pytest.approx(0.525)
    assert s[:, 1].min() == pytest.approx(-0.015) and s[:, 1].max() == pytest.approx(0.015)
    xs = np.unique(np.round(s[:, 0], 9))
    assert np.max(np.diff(xs)) <= 0.003 + 1e-12


def test_every_point_of_a_sampled_face_lies_within_the_slack_of_a_sample():
    b = OrientedBox(np.array([0.5, 0.0, 0.02]), np.eye(3), np.array([0.047, 0.031, 0.04]))
    s = box_samples([b], UP, 0.0, 0.004, 0.0025)
    rng = np.random.default_rng(3)
    probe = np.column_stack([rng.uniform(0.4725, 0.5275, 2000), rng.uniform(-0.0195, 0.0195, 2000)])
    d = np.min(np.hypot(probe[:, None, 0] - s[None, :, 0], probe[:, None, 1] - s[None, :, 1]), axis=1)
    assert np.all(d <= s[:, 3].max() + 1e-12)
    assert s[0, 3] <= 0.5 * np.hypot(0.0025, 0.0025) + 1e-12


def test_check_line_needs_material_on_both_pads_across_their_width():
    lim = LineLimits(HAND, 0.02, 0.005, 0.06, 0.04, 0.01, CFG)
    own = np.array([[c, a, 0.04] for c in np.arange(-0.02, 0.021, 0.003) for a in np.arange(-0.01, 0.011, 0.003)])
    assert check_line(own, np.zeros((0, 3)), 0.0, 0.02, lim).ok
    corner = own[own[:, 1] > 0.006]  # only a strip under the pads' edge
    assert not check_line(corner, np.zeros((0, 3)), -0.004, 0.02, lim).ok


def test_the_source_proposes_fitted_grasps_with_points_and_none_without_a_box_grasp():
    cube = block(0.50, 0.54, 0.00, 0.04, 0.0, 0.04)
    src = GeometricGraspSource(GRASP, HAND, CFG)
    req = GraspRequest((0.52, 0.02), track_of(0, cube), None, PerceivedScene(np.zeros((0, 3))), MAX_WIDTH)
    assert src.propose(req) == []  # no published grasp, no plane: nothing to fall back on
    req = GraspRequest((0.52, 0.02), track_of(0, cube), None, PerceivedScene(np.zeros((0, 3))), MAX_WIDTH,
                       cloud=scene((0, cube), (ENV, table())))
    grasps = src.propose(req)
    assert grasps and abs(grasps[0].width_m - 0.04) < 0.004
    assert len(grasps) == len(src.fitted(req))  # no plane in the scene: no box grasps after them
    R = np.asarray(grasps[0].R)
    assert np.allclose(R[:, 0], [0, 0, -1]) and abs(np.linalg.det(R) - 1) < 1e-9


def test_the_source_says_why_it_proposes_no_grasp():
    src = GeometricGraspSource(GRASP, HAND, CFG)
    wide = block(0.50, 0.60, 0.00, 0.10, 0.0, 0.04)  # 100 mm both ways: wider than the 60 mm opening
    req = GraspRequest((0.55, 0.05), track_of(0, wide), None, PerceivedScene(np.zeros((0, 3))), MAX_WIDTH,
                       cloud=scene((0, wide), (ENV, table())))
    assert src.propose(req) == []
    assert src.last_refusal.startswith("no closing line passes the point checks (") and "box grasps: none" in src.last_refusal
    assert "too wide to close on" in src.last_refusal
    cube = block(0.50, 0.54, 0.00, 0.04, 0.0, 0.04)
    assert src.propose(replace(req, target=track_of(0, cube), cloud=scene((0, cube), (ENV, table()))))
    assert src.last_refusal == ""


def test_a_stack_seen_as_one_cluster_is_grasped_by_its_upper_box():
    lower = block(0.48, 0.56, -0.02, 0.035, 0.0, 0.028)
    upper = block(0.505, 0.535, 0.0, 0.03, 0.028, 0.058)
    merged = np.vstack([upper, lower])
    _, ranked = _fit(track_of(0, merged), scene((0, merged), (ENV, table())))
    assert ranked
    best = ranked[0]
    assert abs(best.width_m - 0.03) < 0.004, best
    assert best.position[2] - HAND.pad_below_tcp_m > 0.028  # pads above the lower box


def test_a_step_never_brings_the_palm_onto_the_object():
    # a bottle: a 60 mm wide body 100 mm tall, a 25 mm neck up to 150 mm (the shoulder is a step)
    body = block(0.47, 0.53, -0.03, 0.03, 0.0, 0.10)
    neck = block(0.4875, 0.5125, -0.0125, 0.0125, 0.10, 0.15)
    bottle = np.vstack([neck, body[~((np.abs(body[:, 0] - 0.5) < 0.0125) & (np.abs(body[:, 1]) < 0.0125)
                                     & (body[:, 2] >= 0.1))]])
    lines, _ = _fit(track_of(0, bottle), scene((0, bottle), (ENV, table())))
    assert any(ln.ok for ln in lines)
    palm_bottom = min(ln.position[2] for ln in lines if ln.ok) + HAND.palm_above_tcp_m
    assert palm_bottom >= 0.15 + GRASP.palm_clearance_m - 1e-9


def test_an_oblique_view_does_not_pull_the_line_off_a_cylinder_axis():
    th = np.linspace(0, 2 * np.pi, 240, endpoint=False)
    top = np.vstack([np.column_stack([0.5 + r * np.cos(th), r * np.sin(th), np.full(th.size, 0.06)])
                     for r in np.r_[np.arange(0.0, 0.0325, 0.003), 0.0325]])
    near = th[np.cos(th) < -0.3]  # the wall facing the camera: many points on one side
    wall = np.vstack([np.column_stack([0.5 + 0.0325 * np.cos(near), 0.0325 * np.sin(near), np.full(near.size, z)])
                      for z in np.arange(0.0, 0.06, 0.002)])
    can = np.vstack([top, wall])
    assert abs(can[:, 0].mean() - 0.5) > 0.008  # the points' mean is pulled to the near wall
    _, ranked = _fit(track_of(0, can), scene((0, can), (ENV, table())))
    assert ranked and abs(ranked[0].width_m - 0.065) < 0.003  # the diameter, not a chord
    assert np.hypot(ranked[0].position[0] - 0.5, ranked[0].position[1]) < 0.004


def test_smeared_edges_of_an_oblique_view_are_clipped_to_the_measured_box():
    cube = block(0.50, 0.54, 0.00, 0.04, 0.0, 0.04)
    smear = np.column_stack([np.full(30, 0.548), np.linspace(0.005, 0.035, 30), np.full(30, 0.03)])
    track = track_of(0, cube)  # the box measured from above: 40 mm
    _, ranked = _fit(track, scene((0, np.vstack([cube, smear])), (ENV, table())))
    assert ranked and all(abs(ln.width_m - 0.04) < 0.0025 for ln in ranked if ln.axis == 0)


@pytest.mark.parametrize("gap_m", [0.0, 0.004, 0.012, 0.016, 0.019])
def test_a_fitted_descent_clears_a_neighbours_box_as_the_planner_measures_it(gap_m):
    """A hand sphere coming straight down beside a neighbour's box must stay the planner's
    margin from the box in 3-D (above its top edge too), as ``OrientedBox.distance_m`` says."""
    from grasp_pipeline.orchestration.grasping.fit import HandSpheres, _sphere_need
    r_m, margin_m = 0.012, 0.005
    box = OrientedBox(np.array([0.0, 0.0, 0.03]), np.eye(3), np.array([0.05, 0.04, 0.06]))
    s = box_samples([box], UP, 0.0, 0.0, 0.0025)
    s[:, 3] += margin_m
    one = HandSpheres(np.zeros((1, 3)), np.zeros((1, 3)), np.array([r_m]))
    x_m = 0.025 + gap_m  # the sphere's line, gap_m beside the box's +x face
    need = _sphere_need(s, 0.0, x_m, 0.0, one)

    def clear(z):
        return box.distance_m(np.array([[x_m, 0.0, z]]))[0] - (r_m + margin_m)

    if gap_m >= r_m + margin_m:  # far enough beside it: down to the table
        assert need == -np.inf and clear(0.0) >= 0.0
        return
    assert clear(need) >= -1e-9  # where the fit lets the hand down, the planner agrees
    assert clear(need) <= s[0, 3] - margin_m + 1e-9  # ... and it keeps no more than the sampling slack


def _box_grasp(closing, centre, width_m):
    """A top-down grasp closing along ``closing`` at ``centre`` (the BestGrasp convention)."""
    return FittedLine(True, "", 0, 0.0, np.asarray(centre, float), np.asarray(closing, float), width_m).grasp(UP)


@pytest.mark.parametrize("closing, blocked", [((1.0, 0.0, 0.0), True), ((0.0, 1.0, 0.0), False)])
def test_a_box_grasp_whose_finger_would_enter_a_neighbour_is_not_offered(closing, blocked):
    cube = block(0.50, 0.54, 0.00, 0.04, 0.0, 0.04)
    walls = [block(0.555, 0.565, -0.03, 0.07, 0.0, 0.05), block(0.475, 0.485, -0.03, 0.07, 0.0, 0.05)]
    cloud = scene((0, cube), (1, walls[0]), (2, walls[1]), (ENV, table()))
    g = _box_grasp(closing, (0.52, 0.02, 0.02), 0.04)  # opens to 60 mm: 10 mm into each wall along x
    why = box_grasp_blocked(track_of(0, cube), cloud, g, HAND, GRASP, CFG, MAX_WIDTH)
    assert bool(why) == blocked and (not why or "finger blocked" in why)


@pytest.mark.parametrize("closing, refused", [((1.0, 0.0, 0.0), False), ((0.0, 1.0, 0.0), True)])
def test_a_box_grasp_whose_hand_meets_a_neighbours_box_is_not_offered(closing, refused):
    """The planner keeps the hand spheres its margin from the neighbours' boxes and refuses the
    pre-grasp otherwise: a box grasp closing towards a towering neighbour 65 mm beyond the cube
    (seen as a box, no points in the finger columns) is not offered — the hand is 214 mm long
    along its closing axis; the one closing across, 150 mm wide that way, is."""
    cube = block(0.50, 0.54, 0.00, 0.04, 0.0, 0.04)
    cloud = scene((0, cube), (ENV, table()))
    towering = OrientedBox(np.array([0.52, 0.135, 0.10]), np.eye(3), np.array([0.06, 0.06, 0.20]))
    g = _box_grasp(closing, (0.52, 0.02, 0.02), 0.04)
    assert box_grasp_blocked(track_of(0, cube), cloud, g, HAND, GRASP, CFG, MAX_WIDTH) == ""  # points only
    why = box_grasp_blocked(track_of(0, cube), cloud, g, HAND, GRASP, CFG, MAX_WIDTH, Neighbours((towering,)), 0.005,
                            planner_hand_spheres(0.04))
    assert bool(why) == refused and (not why or "meets a neighbour" in why)


def test_the_source_offers_a_box_grasp_only_where_its_fingers_come_down_free():
    cube = block(0.50, 0.54, 0.00, 0.04, 0.0, 0.04)
    wall = block(0.555, 0.565, -0.03, 0.07, 0.0, 0.05)
    src = GeometricGraspSource(GRASP, HAND, CFG)
    plane = SimpleNamespace(n=UP, c=0.0)
    track = track_of(0, cube)
    track.smoothed.perp_width_m = 0.04
    along_x = _box_grasp((1.0, 0.0, 0.0), (0.52, 0.02, 0.02), 0.04)
    for parts, offered in (([(0, cube), (ENV, table())], 2), ([(0, cube), (1, wall), (ENV, table())], 1)):
        req = GraspRequest((0.52, 0.02), track, along_x, PerceivedScene(np.zeros((0, 3)), plane=plane), MAX_WIDTH,
                           cloud=scene(*parts))
        assert len(src.from_box(req)) == offered  # the wall takes the x-closing finger's column
    assert len(src.from_box(replace(req, cloud=None))) == 2  # without points: nothing to judge by


def test_the_source_with_the_planners_model_leaves_out_a_box_grasp_the_planner_would_refuse():
    from grasp_pipeline.motion.config import MotionConfig
    cube = block(0.50, 0.54, 0.00, 0.04, 0.0, 0.04)
    towering = OrientedBox(np.array([0.52, 0.135, 0.10]), np.eye(3), np.array([0.06, 0.06, 0.20]))
    track = track_of(0, cube)
    track.smoothed.perp_width_m = 0.04
    along_x = _box_grasp((1.0, 0.0, 0.0), (0.52, 0.02, 0.02), 0.04)  # its perpendicular: along y
    plane = SimpleNamespace(n=UP, c=0.0)
    req = GraspRequest((0.52, 0.02), track, along_x,
                       PerceivedScene(np.zeros((0, 3)), [towering], [1], plane=plane), MAX_WIDTH,
                       cloud=scene((0, cube), (ENV, table())))
    offered = GeometricGraspSource(GRASP, HAND, CFG, MotionConfig()).from_box(req)
    assert len(GeometricGraspSource(GRASP, HAND, CFG).from_box(req)) == 2  # points only: both
    assert len(offered) == 1 and abs(np.asarray(offered[0].R)[0, 2]) > 0.99  # closing along x


def _bottle_top(cx, cy, r_m, h_m):
    """The top disc of an upright bottle as the camera sees it from above."""
    a, rr = np.meshgrid(np.linspace(0, 2 * np.pi, 120), np.linspace(0, r_m, 15))
    return np.c_[cx + (rr * np.cos(a)).ravel(), cy + (rr * np.sin(a)).ravel(), np.full(a.size, h_m)]


def test_a_neighbour_modelled_by_its_points_frees_the_empty_corner_of_its_box():
    """A 200 mm bottle standing diagonally beyond the cube's corner: its box's corner takes the
    hand's path on every line; its points (the planner's columns under them) leave lines free."""
    from grasp_pipeline.motion.object_points import column_tops
    spheres = planner_hand_spheres(0.04)
    cube = block(0.50, 0.54, 0.00, 0.04, 0.0, 0.06)
    top = _bottle_top(0.60, 0.10, 0.03, 0.20)
    cloud = scene((0, cube), (ENV, table()), (1, top))
    box = OrientedBox(np.array([0.60, 0.10, 0.10]), np.eye(3), np.array([0.06, 0.06, 0.20]))
    grid = (0.005 + 0.0043, 0.005, 0.05)

    def free(neighbours):
        lines = fit_lines(track_of(0, cube), cloud, HAND, GRASP, CFG, 0.005, MAX_WIDTH, neighbours, 0.005,
                          spheres, grid)
        return {(ln.axis, round(ln.offset_m, 4)) for ln in lines if ln.ok}

    as_box = free(Neighbours((box,)))
    as_points = free(Neighbours((), column_tops(top, 0.005), 0.005 + 0.0043))
    assert not as_box and as_points
    assert free(Neighbours((box,), column_tops(top, 0.005), 0.005 + 0.0043)) <= as_box  # both: the box rules


@pytest.mark.parametrize("x_m", [0.03, 0.036, 0.04, 0.05])
def test_a_fitted_descent_clears_a_neighbours_points_as_the_planner_measures_them(x_m):
    """Where the fit lets a hand sphere down beside a neighbour's column tops, the planner's
    point obstacles (the columns under those tops) are its margin away."""
    from grasp_pipeline.motion.object_points import ObjectPoints, column_tops, columns
    from grasp_pipeline.orchestration.grasping.fit import HandSpheres, _sphere_need
    r_m, margin_m, cell = 0.012, 0.005, 0.005
    tops = column_tops(_bottle_top(0.0, 0.0, 0.025, 0.12), cell)
    fine = 0.5 * np.sqrt(3.0) * cell
    one = HandSpheres(np.zeros((1, 3)), np.zeros((1, 3)), np.array([r_m]))
    need = _sphere_need(np.c_[tops, np.full(len(tops), margin_m + fine)], 0.0, x_m, 0.0, one)
    planner_pts = ObjectPoints(columns(tops, UP, 0.0, cell), cell, pad_m=0.1)
    z = max(need, 0.0) + np.linspace(0.0, 0.1, 41)
    d = planner_pts.distance_m(np.c_[np.full(len(z), x_m), np.zeros(len(z)), z])
    assert np.all(d - (r_m + margin_m) >= -1e-9)  # from the fit's height up, the planner agrees


def test_a_few_side_column_tops_do_not_bridge_the_step_of_a_box_on_a_bar():
    """A 30 mm cube (top 60 mm) on a bar (top 28 mm), seen as one cluster, with three columns
    whose tops lie between the levels (points on the cube's sides): the bar's level is a step
    when a level needs 4 columns; with every column counting the three bridge the gap."""
    from grasp_pipeline.orchestration.grasping.fit import surface_levels

    g = np.arange(0.0, 0.08, 0.005)
    bar = np.array([(x, y, 0.028) for x in g for y in g[:12]])
    cube = np.array([(x, y, 0.060) for x in g[5:11] for y in g[5:11]])
    sides = np.array([(0.0205, 0.0705, 0.036), (0.0255, 0.0705, 0.044), (0.0305, 0.0705, 0.052)])
    own = np.vstack([bar, cube, sides])
    assert surface_levels(own, 0.005, 0.01, min_columns=4) == [pytest.approx(0.028)]
    assert surface_levels(own, 0.005, 0.01, min_columns=1) == []
