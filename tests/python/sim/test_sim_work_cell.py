"""Which perceived tracks are objects to pick: over the table, not over the tray."""

import pytest

from grasp_pipeline.sim.scenes import reference_scene
from grasp_pipeline.sim.world import SimWorld

MARGIN_M = 0.03  # grasp.target_fixture_margin_m


@pytest.fixture(scope="module")
def cell():
    world = SimWorld(reference_scene())
    try:
        yield world.work_cell
    finally:
        world.close()


def test_objects_on_the_table_are_targets(cell):
    for xy in [(0.45, 0.0), (0.62, -0.2), (0.40, 0.2)]:
        assert cell.pick_target_note(xy, MARGIN_M) is None


def test_the_tray_and_its_rim_are_not_targets(cell):
    # the tray (floor 0.28 m square centred at (0.34, 0.58)); its near rim at y = 0.445 —
    # a rim piece once became a track centred 8 mm outside the tray's footprint, off the table
    assert "tray" in cell.pick_target_note((0.34, 0.58), MARGIN_M) or "table" in cell.pick_target_note((0.34, 0.58), MARGIN_M)
    note = cell.pick_target_note((0.447, 0.437), MARGIN_M)
    assert note is not None


def test_the_wall_behind_the_table_is_not_a_target(cell):
    assert "not over the table top" in cell.pick_target_note((0.98, 0.58), MARGIN_M)
    assert "not over the table top" in cell.pick_target_note((0.90, 0.0), MARGIN_M)
