"""The pipeline on your own robot: :func:`run_robot` (docs/real_robot.md).

The same stages as ``grasp-pipeline run`` (:mod:`.run_loop`: rough view, active scan, picks and
places), on any object implementing the robot protocols (``robot/protocols.py``) — the adapter
of an arm, a gripper and an RGB-D camera — in the work cell of a description file
(:mod:`.work_cell_file`). Every camera frame is checked against the frame contract
(``robot/frame_contract.py``) where it enters the pipeline. Nothing here knows a simulator:
the report has no ground-truth scores, and a pick's ``success`` and ``placed`` are what the
robot itself observed (the gripper's stall and hold, the look into the tray).
"""

from __future__ import annotations

import logging
import time
from pathlib import Path
from typing import Any, Callable, Optional, Sequence

from ..exceptions import GraspPipelineError
from ..orchestration import GraspSource
from ..report.output_lock import output_claim
from ..report.rerun_recorder import RerunRecorder, check_recording_path, import_rerun
from ..report.serialize import check_writable, check_writable_dir, write_json
from ..report.snapshot_recorder import SnapshotRecorder
from ..results import STATUS_FAILED, RunReport
from ..settings import Settings, load_settings
from ..signals import interrupts_raise
from .robot_system import ROBOT_SECTIONS, RobotSystem, build_robot_system
from .run_loop import SNAPSHOTS, Recorders, RunOptions, drive
from .work_cell_file import WorkCellSetup, load_work_cell

log = logging.getLogger("grasp_pipeline.run")


def run_robot(robot: Any, work_cell: str | Path | WorkCellSetup, *, settings: Optional[Settings] = None,
              out_dir: str | Path = "out_robot", json_path: str | Path | None = None,
              select: Optional[Sequence[tuple[float, float]]] = None, scan: bool = True,
              place: bool = True, declutter: bool = False, pick: Sequence[str] = (),
              grasp_source: Optional[GraspSource] = None,
              prepare: Optional[Callable[[RobotSystem], None]] = None,
              rerun: str | Path | None = None, snapshots: bool = True, mark_output: bool = True) -> RunReport:
    """Run the pipeline on ``robot``; returns the report (also written to ``json_path``,
    default ``out_dir/report.json``).

    ``robot``: the adapter (every member of ``grasp_pipeline.robot.protocols.Robot``); the
    arm's joints when the run starts are its start and home joints; it is not closed here.
    ``work_cell``: the work-cell file (the layout of ``config/work_cell.yaml``) or a loaded
    :class:`~.work_cell_file.WorkCellSetup`. ``settings``: the parameter sets of
    :data:`~.robot_system.ROBOT_SECTIONS` (default: the packaged ``config/*.yaml``).
    ``select``, ``scan``, ``place``, ``declutter``, ``pick``, ``grasp_source``: as
    :class:`~.run_loop.RunOptions`. ``prepare(system)``: called once the system is built,
    before anything moves (attach your own recorders to ``system.events``). ``rerun``: also
    record the run into this ``.rrd`` file (the Rerun SDK is an optional extra);
    ``snapshots``: PNGs of the perceived scene after the rough view and the scan in ``out_dir``.

    Ctrl-C (and SIGTERM, in the main thread) stops the run: the arm holds (``robot.hold()``)
    and the report says ``interrupted``; an error of the pipeline ends it ``failed`` with the
    reason, the arm holding. A bad work-cell file or an adapter that lacks a protocol member
    raises before anything moves."""
    wall0 = time.perf_counter()
    settings = settings or load_settings(ROBOT_SECTIONS)
    setup = work_cell if isinstance(work_cell, WorkCellSetup) else load_work_cell(work_cell)
    out_dir = Path(out_dir)
    json_path = out_dir / "report.json" if json_path is None else Path(json_path)
    check_writable_dir(out_dir, "output folder (out_dir)")
    check_writable(json_path, "report file (json_path)")
    if rerun is not None:
        import_rerun()
        check_recording_path(rerun)
    options = RunOptions(select, scan, place, declutter, tuple(pick), grasp_source)
    with output_claim(out_dir, "run_robot", enabled=mark_output) as claim:
        report = RunReport(scene={"name": "robot", "robot": type(robot).__name__, "work_cell": setup.source,
                                  "seed": None, "objects": None},
                           settings=settings.as_dict(), warnings=[claim.warning] if claim.warning else [])
        system = _build(robot, setup, settings, report, wall0, json_path)

        def attach() -> Recorders:
            pictures = SnapshotRecorder(out_dir, SNAPSHOTS).attach(system.events) if snapshots else None
            recording = None if rerun is None else \
                RerunRecorder(rerun, robot, settings.rerun).attach(system.events)
            if prepare is not None:
                prepare(system)
            return Recorders(pictures, None, recording)

        with interrupts_raise():
            drive(system, settings, report, options, attach, wall0, json_path)
    log.info("run on %s: %s, %d pick(s), %d succeeded", type(robot).__name__, report.status,
             len(report.picks), sum(p.success for p in report.picks))
    return report


def _build(robot: Any, setup: WorkCellSetup, settings: Settings, report: RunReport, wall0: float,
           json_path: Path) -> RobotSystem:
    """The system on ``robot``; an adapter that breaks the protocols raises, the report written
    as failed (nothing moved)."""
    try:
        return build_robot_system(robot, setup, settings)
    except GraspPipelineError as exc:
        report.status, report.error = STATUS_FAILED, f"{type(exc).__name__}: {exc}"
        report.timings["wall_s"] = time.perf_counter() - wall0
        write_json(json_path, report)
        raise
