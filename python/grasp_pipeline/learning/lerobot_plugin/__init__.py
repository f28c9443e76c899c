"""``lerobot-eval`` with this environment (LeRobot's plugin mechanism).

LeRobot's command line loads a third-party package given as ``--env.discover_packages_path``
before it parses ``--env.type``; importing this package registers

* the environment config type ``grasp_pipeline`` (a ``lerobot.envs.configs.EnvConfig``:
  ``--env.protocol``, ``--env.objects``, ``--env.image_size``, ``--env.fps``,
  ``--env.episode_length``), and
* the Gymnasium id ``gym_grasp_pipeline/PickPlace-v0`` that LeRobot's ``make_env`` builds for it:
  the environment with its observations in the layout LeRobot's evaluation loop reads
  (:mod:`.layout`: ``pixels/<camera>`` and ``agent_pos``, which it turns back into
  ``observation.images.<camera>`` and ``observation.state``).

    lerobot-eval --env.discover_packages_path=grasp_pipeline.learning.lerobot_plugin \\
        --env.type=grasp_pipeline --env.image_size=64 --policy.path=DIR \\
        --eval.n_episodes=10 --eval.batch_size=1 --policy.device=cpu

Importing it also chooses MuJoCo's headless GL backend (``MUJOCO_GL``, as every
``grasp-pipeline`` command does first), since LeRobot's command does not.

LeRobot's loop passes only those keys, so a policy that takes ``observation.ee_pose`` or depth
as input cannot be evaluated there (``grasp-pipeline eval`` passes every observation).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ...sim.gl_backend import configure_gl

configure_gl()  # LeRobot's command imports this first: MuJoCo renders headless (MUJOCO_GL)

import gymnasium as gym  # noqa: E402
from lerobot.configs.types import FeatureType, PolicyFeature  # noqa: E402
from lerobot.envs.configs import EnvConfig  # noqa: E402

from .layout import CAMERAS, GYM_ID, STATE_SIZE  # noqa: E402

if GYM_ID not in gym.registry:
    gym.register(GYM_ID, entry_point="grasp_pipeline.learning.lerobot_plugin.layout:make_env")


@EnvConfig.register_subclass("grasp_pipeline")
@dataclass
class GraspPipelineEnv(EnvConfig):
    """The environment ``grasp_pipeline/PickPlace-v0`` as LeRobot configures environments."""

    task: str | None = "PickPlace-v0"
    fps: int = 15
    protocol: str = "sparse"
    objects: str = "builtin"
    image_size: int = 256
    episode_length: int = 900
    features: dict = field(default_factory=dict)
    features_map: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        side = int(self.image_size)
        self.features = {"action": PolicyFeature(type=FeatureType.ACTION, shape=(8,)),
                         "agent_pos": PolicyFeature(type=FeatureType.STATE, shape=(STATE_SIZE,))}
        self.features.update({f"pixels/{c}": PolicyFeature(type=FeatureType.VISUAL, shape=(side, side, 3))
                              for c in CAMERAS})
        self.features_map = {"action": "action", "agent_pos": "observation.state",
                             **{f"pixels/{c}": f"observation.images.{c}" for c in CAMERAS}}

    @property
    def package_name(self) -> str:
        return "grasp_pipeline.learning.lerobot_plugin"

    @property
    def gym_id(self) -> str:
        return GYM_ID

    @property
    def gym_kwargs(self) -> dict:
        return {"protocol": self.protocol, "objects": self.objects, "image_size": int(self.image_size),
                "fps": int(self.fps), "max_episode_steps": int(self.episode_length)}
