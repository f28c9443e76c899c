"""Composition roots: where the simulated world is built and wired to the pipeline.

* :mod:`.sim_system` — builds a :class:`~.sim_system.System` (a ``SimWorld`` implementing the
  robot protocols, the perception loop, motion, scan, grasp action, event bus).
* :mod:`.run` — ``grasp-pipeline run``: rough view → scan → picks, the report, recorders.
* :mod:`.run_command` — the ``run``/``demo`` command-line front end.

Only this package, ``grasp_pipeline.sim``, ``grasp_pipeline.evaluation`` and the benchmarks
know the simulator; ``perception``, ``motion`` and ``orchestration`` never import it.
"""
