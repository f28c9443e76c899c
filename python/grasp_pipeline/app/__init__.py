"""Composition roots and the run loop: where a robot is wired to the pipeline and run.

* :mod:`.robot_run` — :func:`run_robot`: the pipeline on your own robot (any object
  implementing ``robot/protocols.py``) in the work cell of a YAML file (docs/real_robot.md).
* :mod:`.robot_system` — :func:`build_robot_system` → :class:`RobotSystem` (perception loop
  fed by contract-checked frames, motion, scan, grasp action, event bus) on any robot.
* :mod:`.work_cell_file` — :func:`load_work_cell`: the work-cell file (table, fixtures, tray,
  camera mount, workspace box); ``config/work_cell.yaml`` is the simulated cell's.
* :mod:`.run_loop` — the stages every robot shares (rough view → scan → picks) and the report.
* :mod:`.sim_system` — the simulated composition root: a ``SimWorld`` wired by
  :mod:`.robot_system`, plus the simulator's ground truth for scoring.
* :mod:`.run` — ``grasp-pipeline run``: the simulated scene, recorders, the run loop.
* :mod:`.run_command` — the ``run``/``demo`` command-line front end.

Only :mod:`.sim_system`, :mod:`.run` and :mod:`.run_command` of this package know the simulator
(with ``grasp_pipeline.sim``, ``grasp_pipeline.evaluation`` and the benchmarks); the run loop,
``perception``, ``motion`` and ``orchestration`` never import it. The names above are imported
on first use (``from grasp_pipeline.app import run_robot``).
"""

from importlib import import_module

_LAZY = {"run_robot": ".robot_run", "RobotSystem": ".robot_system", "build_robot_system": ".robot_system",
         "ROBOT_SECTIONS": ".robot_system", "WorkCellSetup": ".work_cell_file",
         "load_work_cell": ".work_cell_file", "RunOptions": ".run_loop"}

__all__ = sorted(_LAZY)


def __getattr__(name: str):
    if name in _LAZY:
        return getattr(import_module(_LAZY[name], __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
