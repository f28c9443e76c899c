"""Fixtures of the simulator tests: world factory and small motion helpers (min-jerk joint
moves, a top-down TCP pose, IK) so tests can drive the arm without the motion layer."""

from __future__ import annotations

import types

import numpy as np
import pytest

from grasp_pipeline.robot import description as rm
from grasp_pipeline.sim.ik import solve_ik
from grasp_pipeline.sim.world import SimWorld


def _minjerk(q0: np.ndarray, q1: np.ndarray, duration_s: float, n: int = 40):
    t = np.linspace(0.0, duration_s, n)
    s = t / duration_s
    f = 10 * s**3 - 15 * s**4 + 6 * s**5
    fd = (30 * s**2 - 60 * s**3 + 30 * s**4) / duration_s
    return t, q0 + f[:, None] * (q1 - q0), fd[:, None] * (q1 - q0)


def _move(world: SimWorld, q1: np.ndarray, duration_s: float, settle_s: float = 0.3) -> None:
    t, q, qd = _minjerk(world.reference()[0].copy(), np.asarray(q1, float), duration_s)
    end = world.follow_trajectory(t, q, qd)
    world.run_until(end + settle_s)


def _top_down(position: np.ndarray, closing_axis: np.ndarray) -> np.ndarray:
    """TCP pose with z (approach) pointing down and y (closing) along ``closing_axis``."""
    y = np.asarray(closing_axis, float).copy()
    y[2] = 0.0
    y /= np.linalg.norm(y)
    z = np.array([0.0, 0.0, -1.0])
    T = np.eye(4)
    T[:3, :3] = np.column_stack([np.cross(y, z), y, z])
    T[:3, 3] = position
    return T


_ROBOT = rm.load_robot_model()
_F_TCP = rm.flange_T_tcp(_ROBOT)


def _ik_tcp(T_tcp: np.ndarray, q_seed: np.ndarray) -> np.ndarray:
    q, ok = solve_ik(T_tcp, q_seed, _F_TCP, _ROBOT)
    assert ok, f"IK failed for TCP at {T_tcp[:3, 3]}"
    return q


@pytest.fixture
def motion():
    return types.SimpleNamespace(minjerk=_minjerk, move=_move, top_down=_top_down,
                                 ik_tcp=_ik_tcp, robot=_ROBOT)


@pytest.fixture
def make_world():
    worlds: list[SimWorld] = []

    def factory(*args, **kwargs) -> SimWorld:
        w = SimWorld(*args, **kwargs)
        worlds.append(w)
        return w

    yield factory
    for w in worlds:
        w.close()


@pytest.fixture
def renderer_pair():
    """``make(model, h, w) -> (ours, theirs)``: an :class:`RgbdRenderer` and MuJoCo's own
    ``mujoco.Renderer`` of the same size, both without shadows, reflections and skybox (as the
    camera renders); skips only where the session disabled GL. Both are closed afterwards."""
    import os

    import mujoco

    from grasp_pipeline.sim.exceptions import RenderUnavailable
    from grasp_pipeline.sim.gl_backend import GL_OFF_VALUES, new_renderer
    from grasp_pipeline.sim.rgbd_renderer import RgbdRenderer

    made = []

    def make(model, h: int, w: int):
        try:
            ours = new_renderer(model, h, w, RgbdRenderer)
            theirs = new_renderer(model, h, w)
        except RenderUnavailable:
            if os.environ.get("MUJOCO_GL", "").strip().lower() not in GL_OFF_VALUES:
                pytest.fail("no GL renderer although GL was not disabled")
            pytest.skip("MUJOCO_GL disables GL in this test session")
        for r in (ours, theirs):
            for flag in (mujoco.mjtRndFlag.mjRND_SHADOW, mujoco.mjtRndFlag.mjRND_REFLECTION,
                         mujoco.mjtRndFlag.mjRND_SKYBOX):
                r.scene.flags[flag] = 0
        made.extend([ours, theirs])
        return ours, theirs

    yield make
    for r in made:
        r.close()


def mujoco_passes(renderer, data, camera_id: int):
    """MuJoCo's own depth, colour and segmentation passes of a ``mujoco.Renderer``: (depth
    (H, W) float32, colour (H, W, 3) uint8, geom id per pixel (H, W), -1 for none)."""
    import mujoco

    renderer.update_scene(data, camera=camera_id)
    renderer.enable_depth_rendering()
    depth = renderer.render().copy()
    renderer.disable_depth_rendering()
    colour = renderer.render().copy()
    renderer.enable_segmentation_rendering()
    seg = renderer.render().copy()
    renderer.disable_segmentation_rendering()
    return depth, colour, np.where(seg[..., 1] == int(mujoco.mjtObj.mjOBJ_GEOM), seg[..., 0], -1)


@pytest.fixture
def full_scene_passes():
    """:func:`mujoco_passes` as a fixture."""
    return mujoco_passes
