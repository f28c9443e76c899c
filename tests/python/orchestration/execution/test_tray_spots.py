"""Where the held object goes: a free spot with room for it and the hand."""

import numpy as np
import pytest

from grasp_pipeline.motion.planning_world import held_spheres_in_tcp
from grasp_pipeline.motion.robot_spheres import hand_spheres_in_tcp
from grasp_pipeline.orchestration.execution.place import place_orientations
from grasp_pipeline.orchestration.execution.place_config import PlaceConfig
from grasp_pipeline.orchestration.execution.tray import TrayContents, TrayGeometry
from grasp_pipeline.orchestration.execution.tray_spots import (HeldShape, TrayFull, _free,
                                                               _spot_cells, free_spots,
                                                               preferred_positions)
from grasp_pipeline.robot.description import load_robot_model

from .tray_cell import CELL, FLOOR_Z, solid_points

TOP_DOWN = np.array([[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]])  # approach down, closing y


@pytest.fixture(scope="module")
def cube_shape():
    """A 5 cm cube held at its middle from above, fingers open to 7 cm."""
    model = load_robot_model()
    c, r = hand_spheres_in_tcp(model, 0.04, 0.07)
    pts = solid_points(0.05, 0.05, 0.05)
    return HeldShape(pts, *held_spheres_in_tcp(model, pts), c, r)


def spots_for(tray, shape, k=0, cfg=PlaceConfig()):
    preferred = preferred_positions(tray.geometry, k, 0.055)
    return free_spots(tray, shape, place_orientations(TOP_DOWN), preferred, cfg)


def footprint_gap_m(a_xy, b_xy, half_a, half_b):
    """Gap between two axis-aligned square footprints (negative: overlap)."""
    return float(np.max(np.abs(np.asarray(a_xy) - b_xy)) - half_a - half_b)


def test_the_first_object_goes_near_the_first_preferred_corner_inside_the_walls(cube_shape):
    tray = TrayContents(TrayGeometry.from_work_cell(CELL), 0.005, 0.008)
    spot = spots_for(tray, cube_shape)[0]
    pref = preferred_positions(tray.geometry, 0, 0.055)[0]
    assert np.linalg.norm(spot.xy - pref) <= 0.05
    inner = 0.13  # inner faces of the walls from the centre
    assert np.all(np.abs(spot.xy - [0.34, 0.58]) + 0.025 <= inner)
    assert spot.rotations  # free with at least one turn of the hand


def test_an_object_placed_where_a_previous_one_lies_goes_next_to_it(cube_shape):
    tray = TrayContents(TrayGeometry.from_work_cell(CELL), 0.005, 0.008)
    pref = preferred_positions(tray.geometry, 0, 0.055)[0]
    tray.add_released(solid_points(0.05, 0.05, 0.05) + [pref[0], pref[1], FLOOR_Z + 0.03])
    spot = spots_for(tray, cube_shape, k=0)[0]  # the same preferred position again
    gap = footprint_gap_m(spot.xy, pref, 0.025, 0.025)
    assert gap >= 0.005  # not on it: beside it, with room
    assert np.linalg.norm(spot.xy - pref) <= 0.12  # next to it, not across the tray


def test_a_tray_without_floor_room_takes_the_object_on_top_then_says_it_is_full(cube_shape):
    tray = TrayContents(TrayGeometry.from_work_cell(CELL), 0.005, 0.008)
    for x in np.arange(0.245, 0.45, 0.06):
        for y in np.arange(0.485, 0.69, 0.06):
            tray.add_released(solid_points(0.05, 0.05, 0.02) + [x, y, FLOOR_Z + 0.03])
    spot = spots_for(tray, cube_shape)[0]  # no floor left: on top of the flat ones
    grid = tray.geometry.grid(0.01)
    ij = grid.index(spot.xy[None])[0]
    assert tray.heights(grid)[ij[0], ij[1]] == pytest.approx(0.02, abs=0.005)
    tray = TrayContents(TrayGeometry.from_work_cell(CELL), 0.005, 0.008)
    for x in np.arange(0.245, 0.45, 0.06):
        for y in np.arange(0.485, 0.69, 0.06):
            tray.add_released(solid_points(0.04, 0.04, 0.14) + [x, y, FLOOR_Z + 0.1])
    with pytest.raises(TrayFull, match=r"the tray is full: no room for the held object \(50 x 50 x 50 mm\)"):
        spots_for(tray, cube_shape)


def test_after_the_floor_spots_come_spots_on_what_lies_lowest(cube_shape):
    """When the floor has fewer spots than the arm may need (one may be out of reach), the
    list goes on with spots on top of what lies lowest in the tray."""
    tray = TrayContents(TrayGeometry.from_work_cell(CELL), 0.005, 0.008)
    centres = [(x, y) for x in np.arange(0.245, 0.45, 0.06) for y in np.arange(0.485, 0.69, 0.06)]
    gap = [centres[k] for k in (0, 1, 4, 5)]  # one corner's 2 x 2 left empty
    for x, y in centres:
        if (x, y) not in gap:
            tray.add_released(solid_points(0.05, 0.05, 0.02) + [x, y, FLOOR_Z + 0.03])
    spots = spots_for(tray, cube_shape)
    grid, (floor, lowest, higher) = _free(tray, cube_shape, place_orientations(TOP_DOWN), PlaceConfig())
    on_top = lowest | higher
    layer = ["floor" if np.any(floor[(slice(None), *grid.index(s.xy[None])[0])]) else
             "on top" if np.any(on_top[(slice(None), *grid.index(s.xy[None])[0])]) else "?" for s in spots]
    assert layer[0] == "floor" and np.linalg.norm(spots[0].xy - np.mean(gap, axis=0)) <= 0.03
    assert "?" not in layer and layer == sorted(layer) and layer[-1] == "on top"  # floor first, then on top


def test_at_every_spot_the_hand_clears_what_lies_in_the_tray_at_the_release_height(cube_shape):
    """Checked sphere by sphere against the contents' column tops, with the object standing on
    what lies under its points — as the lowering will aim."""
    tray = TrayContents(TrayGeometry.from_work_cell(CELL), 0.005, 0.008)
    for x in (0.23, 0.34, 0.45):  # 6 cm blocks with 6 cm gaps: the cube fits a gap, not its hand
        for y in (0.47, 0.58, 0.69):
            tray.add_released(solid_points(0.05, 0.05, 0.06) + [x, y, FLOOR_Z + 0.05])
    tops = np.vstack([o.tops for o in tray.objects.values()])
    cfg = PlaceConfig()
    for spot in spots_for(tray, cube_shape):
        for R in spot.rotations:
            pts = cube_shape.points_tcp @ R.T + [*spot.xy, 0.0]
            below = tops[np.min(np.linalg.norm(tops[:, None, :2] - pts[None, :, :2], axis=2), axis=1) < 0.005]
            support = float(below[:, 2].max()) if len(below) else FLOOR_Z
            z_tcp = support + cfg.release_clearance_m + cube_shape.bottom_m(R)
            for c, r in zip(cube_shape.hand_centres @ R.T, cube_shape.hand_radii):
                near = tops[np.linalg.norm(tops[:, :2] - (spot.xy + c[:2]), axis=1) <= r]
                if len(near):
                    assert near[:, 2].max() + 0.0025 < z_tcp + c[2] - r, (spot.xy, c)


def test_an_object_rests_on_the_highest_thing_under_its_spheres_or_the_spot_is_not_free():
    """Standing on the floor with a neighbour under the edge of its spheres would release it
    beside that neighbour (lower than the hand was checked for): not a spot; on the neighbour,
    it is one, standing that high."""
    grid = TrayGeometry.from_work_cell(CELL).grid(0.01)
    contents = np.zeros(grid.shape)
    contents[10, 11] = 0.05
    ring = np.array([(i, j) for i in (-1, 0, 1) for j in (-1, 0, 1)])
    stamp = (ring, np.array([[0, 0]]), np.zeros((0, 2), dtype=int), np.zeros(0))
    ok, support = _spot_cells(grid, contents, contents, np.ones(grid.shape, bool), stamp, 0.03, 0.008)
    assert not ok[10, 10] and ok[10, 11] and support[10, 11] == 0.05 and ok[10, 13]


def test_alternative_spots_are_apart(cube_shape):
    tray = TrayContents(TrayGeometry.from_work_cell(CELL), 0.005, 0.008)
    cfg = PlaceConfig()
    spots = spots_for(tray, cube_shape, cfg=cfg)
    assert len(spots) == cfg.arrival_spots
    for i, a in enumerate(spots):
        for b in spots[i + 1:]:
            assert np.linalg.norm(a.xy - b.xy) >= cfg.spot_separation_m - 1e-9


def test_highest_over_cell_runs_equals_the_maximum_of_the_shifted_grids():
    """The run maxima give, per cell, the very largest value of the shifted grids (runs of
    any length, gaps in a row, single cells; no offsets: -inf)."""
    from grasp_pipeline.orchestration.execution.tray_spots import _highest

    rng = np.random.default_rng(3)
    pad, shape = 9, (13, 17)
    a = rng.normal(size=(shape[0] + 2 * pad, shape[1] + 2 * pad))
    a[rng.random(a.shape) < 0.05] = np.inf
    for n in (1, 5, 60, 200):
        offsets = np.unique(rng.integers(-pad, pad + 1, size=(n, 2)), axis=0)
        want = np.full(shape, -np.inf)
        for du, dv in offsets:
            want = np.maximum(want, a[pad + du:pad + du + shape[0], pad + dv:pad + dv + shape[1]])
        assert np.array_equal(_highest(a, offsets, pad, shape), want)
    assert np.all(_highest(a, np.zeros((0, 2), dtype=int), pad, shape) == -np.inf)
