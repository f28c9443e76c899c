"""Learning loop: the environment that matches the recorded datasets, policies in it, and their
evaluation and training.

* :mod:`.interface` — the one definition of observations and actions (``record`` uses it too);
* :mod:`.pick_env` — ``grasp_pipeline/PickPlace-v0``, a Gymnasium environment (optional extra
  ``learning``: ``gymnasium``); registered when this package is imported with Gymnasium
  present, so ``gymnasium.make("grasp_pipeline/PickPlace-v0", protocol="sparse")`` works after
  ``import grasp_pipeline.learning`` (or ``gymnasium.make("grasp_pipeline.learning:grasp_pipeline/PickPlace-v0")``);
* :mod:`.robot_adapter` and :mod:`.reference_policy` — the pipeline acting through the
  environment (the robot protocols implemented on ``step(action)``);
* :mod:`.lerobot_policy` — a policy saved by LeRobot, run in the environment;
* :mod:`.eval_command` (``grasp-pipeline eval``) and :mod:`.train_command` (``grasp-pipeline
  train``).
"""

from __future__ import annotations

from ..exceptions import GraspPipelineError

ENV_ID = "grasp_pipeline/PickPlace-v0"
ENTRY_POINT = "grasp_pipeline.learning.pick_env:PickPlaceEnv"
INSTALL_HINT = "pip install 'grasp-pipeline[learning]' (Gymnasium; in a checkout: pip install '.[learning]')"


class LearningUnavailable(GraspPipelineError):
    """Gymnasium (the optional extra ``learning``) is not installed."""


def require_gymnasium():
    """The ``gymnasium`` module, or :class:`LearningUnavailable` saying how to install it."""
    try:
        import gymnasium
    except ImportError as exc:
        raise LearningUnavailable(f"the learning environment needs Gymnasium ({exc}): {INSTALL_HINT}") from exc
    return gymnasium


def register_env() -> bool:
    """Register :data:`ENV_ID` with Gymnasium (once); False when Gymnasium is missing."""
    try:
        import gymnasium
    except ImportError:
        return False
    if ENV_ID not in gymnasium.registry:
        gymnasium.register(ENV_ID, entry_point=ENTRY_POINT)
    return True


register_env()
