"""Evaluation — the only code besides ``grasp_pipeline.sim`` that reads ground truth.

* :mod:`.scoring` — estimates against the true objects (centre, width, height, yaw errors).
* :mod:`.pick_evaluator` — follows the picked object's true height (lift, hold time) and
  whether it ended in the tray; subscribes to the run's events.

Perception, motion and orchestration never import this package.
"""
