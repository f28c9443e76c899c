"""RgbdRenderer: one render pass gives the depth of MuJoCo's depth pass and the colour of its
colour pass, bit for bit, and the segmentation pass names the same geoms."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from grasp_pipeline.robot.description import CAMERA_NAME
from grasp_pipeline.sim.scenes import reference_scene

H, W = 120, 160


@pytest.mark.parametrize("arm_offset_rad", [0.0, 0.25])
def test_one_pass_equals_mujocos_depth_colour_and_segmentation_passes(
        make_world, renderer_pair, full_scene_passes, arm_offset_rad):
    world = make_world(reference_scene(), camera=False)
    world.data.qpos[:7] += arm_offset_rad  # a second view, from elsewhere
    mujoco.mj_forward(world.model, world.data)
    cam = world.model.camera(CAMERA_NAME).id
    ours, theirs = renderer_pair(world.model, H, W)
    depth, colour, geoms = full_scene_passes(theirs, world.data, cam)

    ours.update_scene(world.data, cam)
    z, rgb = ours.render(rgb=True)
    z_only, none = ours.render(rgb=False)
    assert z.dtype == np.float32 and z.shape == (H, W) and rgb.shape == (H, W, 3)
    assert np.array_equal(z, depth) and np.array_equal(z_only, depth) and none is None
    assert np.array_equal(rgb, colour)
    assert np.array_equal(ours.segmentation(), geoms)
    assert (geoms >= 0).mean() > 0.5 and np.isfinite(z).all()  # the view shows the scene


def test_closed_renderer_refuses_and_closes_twice(make_world, renderer_pair):
    world = make_world(reference_scene(), camera=False)
    ours, theirs = renderer_pair(world.model, H, W)
    theirs.close()
    ours.close()
    ours.close()
    with pytest.raises(RuntimeError):
        ours.render()
