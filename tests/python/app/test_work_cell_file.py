"""The work-cell file: config/work_cell.yaml is the simulated cell (the cell the simulator reads
from its MuJoCo model equals it), a user's file loads into the same types, and a bad file is
refused with one line naming the file and the entry (millimetres, typos, a tray without floor)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

from grasp_pipeline.app.work_cell_file import default_work_cell_path, load_work_cell, parse_work_cell
from grasp_pipeline.exceptions import ConfigError

EXAMPLE_CELL = Path(__file__).resolve().parents[3] / "examples" / "own_robot" / "work_cell.yaml"


def _same_box(a, b) -> None:
    np.testing.assert_allclose(a.center, b.center, atol=1e-12)
    np.testing.assert_allclose(a.R, b.R, atol=1e-12)
    np.testing.assert_allclose(a.extents, b.extents, atol=1e-12)


def test_the_simulated_cell_read_from_the_model_equals_config_work_cell_yaml():
    from grasp_pipeline.app.sim_system import sim_work_cell
    from grasp_pipeline.sim.world import SimWorld

    with SimWorld(camera=False) as world:
        model = sim_work_cell(world)  # what build_system wires the simulated run with
    told = load_work_cell()
    _same_box(model.cell.table, told.cell.table)
    assert len(model.cell.fixtures) == len(told.cell.fixtures) == 6
    for a, b in zip(model.cell.fixtures, told.cell.fixtures):
        _same_box(a, b)
    np.testing.assert_allclose(model.cell.tray_center_m, told.cell.tray_center_m, atol=1e-12)
    _same_box(model.cell.tray_floor, told.cell.tray_floor)
    np.testing.assert_allclose(model.flange_T_camera, told.flange_T_camera, atol=1e-12)
    assert model.workspace_box_m == told.workspace_box_m == ()
    assert told.table_top_z_m == pytest.approx(world.scene.table_top_z_m, abs=1e-12)


def test_a_users_file_loads_with_its_own_tray_and_workspace_box():
    setup = load_work_cell(EXAMPLE_CELL)
    assert setup.cell.tray_center_m[1] < 0 and setup.fixture_names[1] == "tray_floor"
    assert setup.workspace().enabled and setup.workspace_box_m == (0.0, 1.0, -0.9, 0.9, 0.1, 0.9)
    assert setup.cell.pick_target_note((0.5, 0.0), 0.02) is None
    assert "is not over the table top" in setup.cell.pick_target_note((0.34, -0.58), 0.02)
    assert "fixture (the tray)" in setup.cell.pick_target_note((0.34, -0.39), 0.06)


def test_a_camera_mount_as_a_quaternion_equals_the_same_rotation_in_rpy():
    data = yaml.safe_load(default_work_cell_path().read_text())
    s = np.sin(np.radians(22.5))
    data["camera_mount"] = {"xyz_m": data["camera_mount"]["xyz_m"], "quat_xyzw": [0.0, 0.0, s, np.cos(np.radians(22.5))]}
    np.testing.assert_allclose(parse_work_cell(data).flange_T_camera, load_work_cell().flange_T_camera, atol=1e-12)


def _edit(change) -> dict:
    data = yaml.safe_load(default_work_cell_path().read_text())
    change(data)
    return data


@pytest.mark.parametrize("change, words", [
    (lambda d: d.pop("table"), ["table is missing"]),
    (lambda d: d.update(fixture=[]), ["unknown entry fixture", "known: table, fixtures"]),
    (lambda d: d["table"].update(center_m=[550.0, 0.0, 190.0]), ["table.center_m", "millimetres?"]),
    (lambda d: d["table"].update(size_m=[0.6, 0.8]), ["table.size_m must be 3 numbers"]),
    (lambda d: d["table"].update(size_m=[0.6, -0.8, 0.02]), ["table.size_m must be positive"]),
    (lambda d: d["fixtures"][2].update(colour="red"), ["unknown entry fixtures[2].colour"]),
    (lambda d: d["fixtures"][3].update(name="tray_wall0"), ["fixtures[3] needs a name of its own"]),
    (lambda d: d["tray"].update(floor="tray_flor"), ["tray.floor must name one of the fixtures", "tray_floor"]),
    (lambda d: d["tray"].update(center_m=[0.34, 0.58, 0.3]), ["must lie on the top of its floor"]),
    (lambda d: d["camera_mount"].update(xyz_m=[37.1, -37.1, 33.5]), ["millimetres"]),
    (lambda d: d["camera_mount"].update(xyz_m=[0.4, 0.3, 0.2]), ["from the flange", "metres"]),
    (lambda d: d["camera_mount"].update(quat_xyzw=[0, 0, 0, 1]), ["exactly one of rpy_deg"]),
    (lambda d: d["camera_mount"].pop("rpy_deg") and d["camera_mount"].update(quat_xyzw=[0, 0, 0.5, 0.5]),
     ["unit quaternion"]),
    (lambda d: d.update(workspace_box_m=[0, 1, 0, 1, 0.5, 0.1]), ["workspace_box_m", "minimum below its maximum"]),
    (lambda d: d.update(table="the big one"), ["table must be a mapping"]),
])
def test_a_bad_work_cell_is_refused_with_one_line_naming_the_entry(change, words):
    with pytest.raises(ConfigError) as info:
        parse_work_cell(_edit(change), "my_cell.yaml")
    msg = str(info.value)
    assert "\n" not in msg and msg.startswith("my_cell.yaml: "), msg
    assert all(w in msg for w in words), msg


def test_a_missing_file_says_what_to_start_from(tmp_path):
    with pytest.raises(ConfigError, match="not found; start from a copy of .*work_cell.yaml"):
        load_work_cell(tmp_path / "cell.yaml")


def test_a_cell_without_a_tray_loads():
    setup = parse_work_cell(_edit(lambda d: d.update(tray=None)))
    assert setup.cell.tray_center_m is None and setup.cell.tray_floor is None
