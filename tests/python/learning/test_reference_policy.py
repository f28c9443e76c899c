"""The reference policy reads the task sentence with the language resolver's words."""

from grasp_pipeline.language.config import LanguageConfig
from grasp_pipeline.learning.reference_policy import task_description

TEMPLATE = "pick up the {object} and put it in the tray"


def test_the_description_keeps_the_words_the_resolver_knows():
    cfg = LanguageConfig()
    assert task_description("pick up the red mug and put it in the tray", TEMPLATE, cfg) == "the red mug"
    assert task_description("pick up the blue cuboid and put it in the tray", TEMPLATE, cfg) == "the blue cuboid"
    assert task_description("pick up the yellow triangular prism and put it in the tray", TEMPLATE, cfg) \
        == "the yellow object"
    assert task_description("pick up the soda can and put it in the tray", TEMPLATE, cfg) == "the can"


def test_the_pipeline_commands_the_robot_only_through_step_and_succeeds():
    """A whole episode of the reference policy: the simulated robot's command methods are
    called only by the environment's action interface, and the target ends in the tray."""
    import sys

    from grasp_pipeline.learning.pick_env import PickPlaceEnv
    from grasp_pipeline.learning.reference_policy import ReferencePolicy
    from grasp_pipeline.sim.world import SimWorld

    callers = set()
    originals = {name: getattr(SimWorld, name) for name in ("follow_trajectory", "set_gripper", "hold", "step")}

    def spy(name):
        def call(self, *args, **kwargs):
            frame = sys._getframe(1)
            callers.add((name, frame.f_code.co_name, frame.f_code.co_filename.rsplit("/", 1)[-1]))
            return originals[name](self, *args, **kwargs)
        return call

    env = PickPlaceEnv("sparse", image_size=32, overrides=(None, ("sim.object_count=[1,1]",)))
    try:
        for name in originals:
            setattr(SimWorld, name, spy(name))
        obs, info = env.reset(seed=3)
        out = ReferencePolicy(env.settings).run_episode(env, obs, info)
    finally:
        for name, fn in originals.items():
            setattr(SimWorld, name, fn)
        env.close()
    assert callers == {(n, "apply", "interface.py") for n in ("follow_trajectory", "set_gripper", "step")}
    assert out.terminated and not out.truncated and out.failed_stage == "" and out.steps > 100
