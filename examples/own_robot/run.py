"""Run the pipeline on your own robot — here the toy hardware, through its adapter.

    PYTHONPATH=python python examples/own_robot/run.py --out /tmp/own_robot

The toy cell is built where the work-cell file (``work_cell.yaml``) says the table and the
tray are, two boxes stand on the table, and the adapter (``adapter.py``) is handed to
``grasp_pipeline.app.run_robot``: the same stages as ``grasp-pipeline run`` (rough view, active
scan, pick and place each box), on any robot. The report is written to ``--out``.
"""

from __future__ import annotations

import argparse
import logging
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from grasp_pipeline.app import load_work_cell, run_robot  # noqa: E402
from grasp_pipeline.logs import setup_logging  # noqa: E402
from grasp_pipeline.robot.description import READY_Q  # noqa: E402

from adapter import OwnRobot  # noqa: E402
from toy_hardware import ToyBox, ToyHardware  # noqa: E402

WORK_CELL = HERE / "work_cell.yaml"
#: The boxes on the table: name, centre (x, y) [m], sizes [m], yaw [deg].
OBJECTS = (("cube", (0.50, -0.08), (0.05, 0.05, 0.05), 20.0),
           ("box", (0.56, 0.09), (0.04, 0.06, 0.045), -15.0))


def build_robot(work_cell=WORK_CELL, objects=OBJECTS, robot_class=OwnRobot):
    """(adapter, toy hardware): the toy cell where ``work_cell`` puts table and fixtures, the
    ``objects`` standing on the table, the arm at the ready joints."""
    setup = load_work_cell(work_cell)
    cell = setup.cell
    fixed = [ToyBox("table", cell.table.center, cell.table.R, cell.table.extents)]
    fixed += [ToyBox(name, b.center, b.R, b.extents) for name, b in zip(setup.fixture_names, cell.fixtures)]
    top = setup.table_top_z_m
    boxes = [ToyBox.upright(name, (x, y, top + 0.5 * size[2]), size, yaw, movable=True)
             for name, (x, y), size, yaw in objects]
    hardware = ToyHardware(READY_Q, fixed + boxes, setup.flange_T_camera)
    return robot_class(hardware, setup.flange_T_camera), hardware


def run_example(out_dir, snapshots: bool = True, robot_class=OwnRobot):
    """Build the toy robot and run the pipeline on it; (report, toy hardware)."""
    robot, hardware = build_robot(robot_class=robot_class)
    return run_robot(robot, WORK_CELL, out_dir=out_dir, snapshots=snapshots), hardware


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="out_own_robot", help="output folder (report.json, snapshots)")
    parser.add_argument("--no-snapshots", action="store_true", help="write no PNG snapshots")
    args = parser.parse_args(argv)
    setup_logging(logging.INFO)
    report, hardware = run_example(args.out, snapshots=not args.no_snapshots)
    for p in report.picks:
        print(f"pick at ({p.anchor[0]:.3f}, {p.anchor[1]:.3f}): "
              f"{'picked' if p.success else 'FAILED at ' + str(p.failed_stage)}, placed {p.placed}")
    print(f"status: {report.status}{'' if not report.error else ' — ' + report.error}")
    for box in hardware.boxes:
        if box.movable:
            print(f"{box.name} now at ({box.center[0]:.3f}, {box.center[1]:.3f}, {box.center[2]:.3f})")
    return 0 if report.all_picked else 1


if __name__ == "__main__":
    sys.exit(main())
