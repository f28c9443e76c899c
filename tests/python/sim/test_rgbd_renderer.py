"""RgbdRenderer: one render pass gives the depth of MuJoCo's depth pass and the colour of its
colour pass, bit for bit, and the segmentation pass names the same geoms."""

from __future__ import annotations

import os

import mujoco
import numpy as np
import pytest

from grasp_pipeline.robot.description import CAMERA_NAME
from grasp_pipeline.sim.exceptions import RenderUnavailable
from grasp_pipeline.sim.gl_backend import GL_OFF_VALUES, new_renderer
from grasp_pipeline.sim.rgbd_renderer import RgbdRenderer
from grasp_pipeline.sim.scenes import reference_scene

H, W = 120, 160
_OFF = (mujoco.mjtRndFlag.mjRND_SHADOW, mujoco.mjtRndFlag.mjRND_REFLECTION, mujoco.mjtRndFlag.mjRND_SKYBOX)


def _renderers(model):
    try:
        ours = new_renderer(model, H, W, RgbdRenderer)
        theirs = new_renderer(model, H, W)
    except RenderUnavailable:
        if os.environ.get("MUJOCO_GL", "").strip().lower() not in GL_OFF_VALUES:
            pytest.fail("no GL renderer although GL was not disabled")
        pytest.skip("MUJOCO_GL disables GL in this test session")
    for r in (ours, theirs):
        for flag in _OFF:
            r.scene.flags[flag] = 0
    return ours, theirs


@pytest.mark.parametrize("arm_offset_rad", [0.0, 0.25])
def test_one_pass_equals_mujocos_depth_colour_and_segmentation_passes(make_world, arm_offset_rad):
    world = make_world(reference_scene(), camera=False)
    world.data.qpos[:7] += arm_offset_rad  # a second view, from elsewhere
    mujoco.mj_forward(world.model, world.data)
    cam = world.model.camera(CAMERA_NAME).id
    ours, theirs = _renderers(world.model)
    try:
        theirs.update_scene(world.data, camera=cam)
        theirs.enable_depth_rendering()
        depth = theirs.render().copy()
        theirs.disable_depth_rendering()
        colour = theirs.render().copy()
        theirs.enable_segmentation_rendering()
        seg = theirs.render().copy()
        geoms = np.where(seg[..., 1] == int(mujoco.mjtObj.mjOBJ_GEOM), seg[..., 0], -1)

        ours.update_scene(world.data, cam)
        z, rgb = ours.render(rgb=True)
        z_only, none = ours.render(rgb=False)
        assert z.dtype == np.float32 and z.shape == (H, W) and rgb.shape == (H, W, 3)
        assert np.array_equal(z, depth) and np.array_equal(z_only, depth) and none is None
        assert np.array_equal(rgb, colour)
        assert np.array_equal(ours.segmentation(), geoms)
        assert (geoms >= 0).mean() > 0.5 and np.isfinite(z).all()  # the view shows the scene
    finally:
        ours.close()
        theirs.close()


def test_closed_renderer_refuses_and_closes_twice(make_world):
    world = make_world(reference_scene(), camera=False)
    ours, theirs = _renderers(world.model)
    theirs.close()
    ours.close()
    ours.close()
    with pytest.raises(RuntimeError):
        ours.render()
