"""Evaluation — the only code besides ``grasp_pipeline.sim`` that reads ground truth.

* :mod:`.scoring` — estimates against the true objects (centre, width, height, yaw errors).
* :mod:`.pick_evaluator` — follows the picked object's true height (lift, hold time) and
  whether it ended in the tray; subscribes to the run's events.
* :mod:`.grasp_bound` — each object's geometric bound: graspable by the hand from above, with a
  tilted approach, from some side, or not at all (from its true hull and pose).
* :mod:`.object_outcomes` — what happened to each object of a clutter round (picked, attempted
  and failed, never proposed and why, ...), beside its bound; subscribes to the run's events.

Perception, motion and orchestration never import this package.
"""
