"""Where the held object goes: a free spot with room for it and the hand."""

import numpy as np
import pytest

from grasp_pipeline.motion.planning_world import held_spheres_in_tcp
from grasp_pipeline.motion.robot_spheres import hand_spheres_in_tcp
from grasp_pipeline.orchestration.execution.place import place_orientations
from grasp_pipeline.orchestration.execution.place_config import PlaceConfig
from grasp_pipeline.orchestration.execution.tray import TrayContents, TrayGeometry
from grasp_pipeline import _core
from grasp_pipeline.orchestration.execution.tray_spots import (HeldShape, TrayFull, _free,
                                                               free_spots, preferred_positions)
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
    # a disc of 8 mm on 1 cm cells, no spacing: the 3 x 3 cells around the TCP's
    ok, support = _core.tray_spot_cells(
        contents, contents, np.ones(grid.shape, bool), 0.03, 0.01, np.zeros((1, 2)), np.array([0.008]),
        np.array([[0, 0]]), np.zeros((0, 2)), np.zeros(0), np.zeros(0), 0.0, 0.008)
    assert not ok[10, 10] and ok[10, 11] and support[10, 11] == 0.05 and ok[10, 13]


def test_alternative_spots_are_apart(cube_shape):
    tray = TrayContents(TrayGeometry.from_work_cell(CELL), 0.005, 0.008)
    cfg = PlaceConfig()
    spots = spots_for(tray, cube_shape, cfg=cfg)
    assert len(spots) == cfg.arrival_spots
    for i, a in enumerate(spots):
        for b in spots[i + 1:]:
            assert np.linalg.norm(a.xy - b.xy) >= cfg.spot_separation_m - 1e-9


def _cells_near(xy, r, pad_m, cell_m):
    """The numpy formulation: offsets of the cells within ``pad_m`` of any disc."""
    reach = pad_m + 0.5 * np.sqrt(2.0) * cell_m
    lo = np.floor((xy - r[:, None]).min(axis=0) / cell_m - 1 - reach / cell_m).astype(int)
    hi = np.ceil((xy + r[:, None]).max(axis=0) / cell_m + 1 + reach / cell_m).astype(int)
    I, J = np.meshgrid(np.arange(lo[0], hi[0] + 1), np.arange(lo[1], hi[1] + 1), indexing="ij")
    off = np.c_[I.ravel(), J.ravel()]
    d = np.linalg.norm(off[:, None] * cell_m - xy[None], axis=2) - r[None]
    return off[np.min(d, axis=1) <= reach]


def _highest(a, offsets, pad, shape):
    """Per cell, the largest of ``a`` (padded by ``pad``) over the cells at ``offsets``."""
    out = np.full(shape, -np.inf)
    for du, dv in offsets:
        out = np.maximum(out, a[pad + du:pad + du + shape[0], pad + dv:pad + dv + shape[1]])
    return out


def _reference_spot_cells(contents, heights, inside, rim, cell, oxy, orad, under, hxy, hrad, hlim,
                          spacing, tol):
    """(ok, support) by the rules, cell by cell, from shifted grids."""
    obj = _cells_near(oxy, orad, spacing, cell)
    lowest = {}
    for xy, r, lim in zip(hxy, hrad, hlim):
        for c in map(tuple, _cells_near(xy[None], np.array([r]), spacing, cell)):
            lowest[c] = min(lowest.get(c, np.inf), lim)
    hand = np.array(list(lowest), dtype=int).reshape(-1, 2)
    limits = np.array(list(lowest.values()))
    pad = int(max(np.abs(obj).max(initial=0), np.abs(hand).max(initial=0), np.abs(under).max(initial=0)))
    C = np.pad(contents, pad, constant_values=np.inf)
    inside_p = np.pad(inside, pad, constant_values=False)
    H = np.pad(heights, pad, constant_values=rim)
    around = np.maximum(_highest(np.where(inside_p, C, np.inf), obj, pad, contents.shape), 0.0)
    support = np.maximum(_highest(C, under, pad, contents.shape), 0.0)
    ok = np.isfinite(around) & (around <= support + tol)
    for lim in np.unique(limits):
        ok &= _highest(H, hand[limits == lim], pad, contents.shape) <= lim + support
    return ok, support


def test_the_core_spot_cells_follow_the_rules_cell_by_cell():
    """Random trays (contents, walls, cells outside the floor) and stamps (object discs, cells
    under the object, hand discs with their limits): the same verdicts and supports as the
    rules applied cell by cell, on cells of 5 mm and 1 cm."""
    rng = np.random.default_rng(7)
    free = blocked = 0
    for trial in range(12):
        cell = (0.005, 0.01)[trial % 2]
        nu, nv = rng.integers(8, 30, size=2)
        contents = np.where(rng.random((nu, nv)) < 0.03, rng.uniform(0.0, 0.08, (nu, nv)), 0.0)
        heights = np.maximum(contents, np.where(rng.random((nu, nv)) < 0.03, 0.05, 0.0))
        inside = rng.random((nu, nv)) > 0.03
        oxy = rng.normal(0.0, 0.01, (int(rng.integers(1, 8)), 2))
        orad = rng.uniform(0.003, 0.02, len(oxy))
        under = rng.integers(-2, 3, size=(int(rng.integers(0, 12)), 2))
        hxy = rng.normal(0.0, 0.02, (int(rng.integers(0, 12)), 2))
        hrad = rng.uniform(0.005, 0.02, len(hxy))
        hlim = np.round(rng.uniform(0.0, 0.2, len(hxy)), 2)  # rounded: spheres share limits
        args = (contents, heights, inside, 0.06, cell, oxy, orad, under, hxy, hrad, hlim, 0.004, 0.008)
        ok, support = _core.tray_spot_cells(*args)
        want_ok, want_support = _reference_spot_cells(*args)
        assert np.array_equal(ok, want_ok) and np.array_equal(support, want_support), trial
        free, blocked = free + int(ok.sum()), blocked + int((~ok).sum())
    assert free > 100 and blocked > 100  # both verdicts are exercised


def test_the_core_spot_cells_refuse_bad_arrays_with_a_clear_error():
    z = np.zeros((4, 4))
    good = (z, z, np.ones((4, 4), bool), 0.06, 0.01, np.zeros((1, 2)), np.array([0.01]),
            np.zeros((0, 2), dtype=np.int64), np.zeros((0, 2)), np.zeros(0), np.zeros(0), 0.004, 0.008)
    _core.tray_spot_cells(*good)
    with pytest.raises(ValueError, match="heights"):
        _core.tray_spot_cells(z, np.zeros((3, 4)), *good[2:])
    with pytest.raises(TypeError, match="under"):
        _core.tray_spot_cells(*good[:7], np.zeros((2, 2)), *good[8:])
    with pytest.raises(ValueError, match="object_r"):
        _core.tray_spot_cells(*good[:6], np.array([0.01, 0.02]), *good[7:])
