"""The robot protocols on top of the environment: commands only change the next actions;
the clock steps the environment one action at a time; the episode's end stops the pipeline."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

from grasp_pipeline.learning.pick_env import PickPlaceEnv
from grasp_pipeline.learning.robot_adapter import EnvRobot, EpisodeEnded, JointReference
from grasp_pipeline.robot.protocols import Robot


class Steps(gym.Wrapper):
    """Counts the actions sent to the environment."""

    def __init__(self, env):
        super().__init__(env)
        self.actions = []

    def step(self, action):
        self.actions.append(np.asarray(action, float).copy())
        return self.env.step(action)


def test_joint_reference_is_linear_or_cubic_and_holds_outside():
    t, q = np.array([1.0, 2.0]), np.array([np.zeros(7), np.ones(7)])
    lin = JointReference(t, q, None)
    assert np.allclose(lin.sample(1.5)[0], 0.5) and np.allclose(lin.sample(1.5)[1], 1.0)
    assert np.allclose(lin.sample(0.0)[0], 0.0) and np.allclose(lin.sample(9.0)[1], 0.0)
    cub = JointReference(t, q, np.zeros((2, 7)))
    assert np.allclose(cub.sample(1.5)[0], 0.5) and np.allclose(cub.sample(1.25)[0], 0.15625)


@pytest.fixture
def robot():
    env = Steps(PickPlaceEnv("sparse", image_size=32, overrides=(None, ("sim.object_count=[1,1]",)),
                             max_episode_steps=5))
    obs, info = env.reset(seed=3)
    yield EnvRobot(env, obs, info), env
    env.close()


def test_commands_go_out_only_as_actions(robot):
    r, env = robot
    assert isinstance(r, Robot)
    q0 = r.q.copy()
    end = r.follow_trajectory(np.array([0.0, 1.0]), np.vstack([q0, q0 + 0.1]))
    r.set_gripper(0.02)
    r.hold(q0)
    r.follow_trajectory(np.array([0.0, 1.0]), np.vstack([q0, q0 + 0.1]))
    assert env.actions == [] and end == pytest.approx(1.0)
    r.step(2)
    assert len(env.actions) == 2
    period = env.unwrapped.control_period_s
    for k, a in enumerate(env.actions, start=1):   # the trajectory at the time the action is reached
        assert np.allclose(a[:7], q0 + 0.1 * k * period, atol=2e-3) and a[7] == pytest.approx(0.02)
    assert r.time_s == pytest.approx(2 * period, abs=0.003)
    assert np.allclose(r.q, env.unwrapped.world.q, atol=1e-6)       # readings from the observation


def test_the_episode_end_stops_the_pipeline(robot):
    r, env = robot
    with pytest.raises(EpisodeEnded) as ended:
        r.step(10)
    assert len(env.actions) == 5 and not ended.value.terminated
    with pytest.raises(EpisodeEnded):
        r.step()
    assert len(env.actions) == 5
