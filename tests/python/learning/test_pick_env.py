"""The environment: registered with Gymnasium; deterministic for a seed; its actions held for
one control period; bad actions refused; truncated at its time limit with the reason."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

from grasp_pipeline.exceptions import InputError
from grasp_pipeline.learning.interface import InvalidAction
from grasp_pipeline.learning.pick_env import PickPlaceEnv

PX = 32  # tiny images: these tests are about the dynamics, not the pictures
ONE = (None, ("sim.object_count=[2,2]",))


@pytest.fixture(scope="module")
def env():
    e = PickPlaceEnv("sparse", image_size=PX, overrides=ONE, max_episode_steps=4)
    yield e
    e.close()


def _actions(obs, n=4):
    """A short wiggle of the arm from where it stands and a gripper half closing."""
    q0 = np.asarray(obs["observation.state"][:7], float)
    return [np.append(q0 + 0.05 * np.sin(k + np.arange(7)), 0.04).astype(np.float32) for k in range(n)]


def _episode(env, seed):
    obs, info = env.reset(seed=seed)
    out = [(obs, info)]
    for a in _actions(obs):
        obs, r, term, trunc, info = env.step(a)
        out.append((obs, info, r, term, trunc))
    return out


def test_registered_with_gymnasium():
    import grasp_pipeline.learning  # noqa: F401  (registers on import)

    e = gym.make("grasp_pipeline/PickPlace-v0", image_size=PX, overrides=ONE)
    assert isinstance(e.unwrapped, PickPlaceEnv)
    e.close()


def test_same_seed_same_episode_and_another_seed_another_scene(env):
    a, b = _episode(env, 5), _episode(env, 5)
    for x, y in zip(a, b):
        for key in x[0]:
            assert np.array_equal(x[0][key], y[0][key]), key
        assert x[1]["task"] == y[1]["task"] and x[1]["time_s"] == y[1]["time_s"]
    c = _episode(env, 6)
    assert not np.array_equal(c[0][0]["observation.images.scene"], a[0][0]["observation.images.scene"])


def test_an_action_is_reached_at_the_next_control_time(env):
    obs, info = env.reset(seed=5)
    assert info["time_s"] == 0.0 and info["step"] == 0
    target = _actions(obs, 1)[0]
    target[:7] = obs["observation.state"][:7] + 0.01
    obs, _r, _t, _tr, info = env.step(target)
    assert info["time_s"] == pytest.approx(1.0 / env.fps, abs=env.world.timestep_s)
    # the joint reference ends the period on the action's targets (held after it)
    q_ref, _ = env.world.reference()
    assert np.allclose(q_ref, target[:7], atol=1e-6)
    assert np.max(np.abs(obs["observation.state"][:7] - target[:7])) < 0.005


def test_bad_actions_are_refused_and_out_of_range_ones_clipped(env):
    obs, _ = env.reset(seed=5)
    with pytest.raises(InvalidAction, match="8 numbers"):
        env.step(np.zeros(7))
    with pytest.raises(InvalidAction, match="NaN"):
        env.step(np.full(8, np.nan))
    big = np.append(obs["observation.state"][:7], 1.0)        # a 1 m gap: clipped to 0.08 m
    env.step(big)
    assert env.interface.targets[7] == pytest.approx(0.08)


def test_truncated_at_the_time_limit_with_where_the_target_is(env):
    steps = _episode(env, 5)
    assert [s[4] for s in steps[1:]] == [False, False, False, True]
    assert not any(s[3] for s in steps[1:]) and all(s[2] == 0.0 for s in steps[1:])
    info = steps[-1][1]
    assert info["failure_reason"].startswith("time limit (4 steps") and "the target is on the table" in info["failure_reason"]
    assert info["is_success"] is False and info["target"] in {o.name for o in env.scene.objects}


def test_bad_options_are_refused():
    with pytest.raises(InputError, match="protocol must be one of"):
        PickPlaceEnv("heap")
    e = PickPlaceEnv("sparse", image_size=PX, overrides=ONE)
    with pytest.raises(gym.error.ResetNeeded):
        e.step(np.zeros(8))
    with pytest.raises(InputError, match="is not an object of scene 5"):
        e.reset(seed=5, options={"target": "nothing_here"})
    e.close()


def test_with_depth_the_depth_images_are_observations_too():
    e = PickPlaceEnv("sparse", depth=True, image_size=PX, overrides=ONE)
    obs, _ = e.reset(seed=5)
    for cam in ("wrist", "scene"):
        d = obs[f"observation.depth.{cam}"]
        assert d.shape == (PX, PX, 1) and d.dtype == np.float32 and float(d.max()) > 0.1
    assert e.observation_space.contains(obs)
    e.close()
