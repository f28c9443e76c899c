"""The camera's draw order: geoms out of view are left out, planes drawn last, the model's
geom groups restored — and the images (depth, colour, segmentation) are MuJoCo's full scene's,
bit for bit, from views where the arm's own links lie on the frustum's edges."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from grasp_pipeline.robot.description import CAMERA_NAME
from grasp_pipeline.sim.draw_order import DrawOrder, out_of_view
from grasp_pipeline.sim.scenes import reference_scene

H, W = 96, 128


def test_spheres_inside_on_the_edge_and_outside_the_frustum():
    T = np.eye(4)  # camera at the origin looking along -z, 90 deg vertical field of view
    tan_v, aspect, near = 1.0, 1.0, 0.05
    centres = np.array([
        [0.0, 0.0, -1.0],    # on the axis
        [1.5, 0.0, -1.0],    # beside the view, its sphere short of the side plane
        [1.02, 0.0, -1.0],   # just outside, but the sphere reaches in
        [0.0, 0.0, 1.0],     # behind the camera
        [0.0, 0.0, 0.04],    # behind, the sphere reaching past the near plane
        [0.0, -3.0, -1.0],   # far below the view
    ])
    radii = np.array([0.1, 0.1, 0.1, 0.1, 0.2, 0.5])
    assert out_of_view(centres, radii, T, tan_v, aspect, near).tolist() == [
        False, True, False, True, False, True]
    # the same, with the camera turned and moved: only relative positions matter
    R = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    T2 = np.eye(4)
    T2[:3, :3], T2[:3, 3] = R, [0.3, -0.2, 0.5]
    moved = centres @ R.T + T2[:3, 3]
    assert np.array_equal(out_of_view(moved, radii, T2, tan_v, aspect, near),
                          out_of_view(centres, radii, T, tan_v, aspect, near))


def test_wider_images_see_farther_sideways():
    T = np.eye(4)
    c, r = np.array([[1.5, 0.0, -1.0]]), np.array([0.05])
    assert out_of_view(c, r, T, math.tan(math.radians(30)), 1.0, 0.05)[0]
    assert not out_of_view(c, r, T, math.tan(math.radians(30)), 3.0, 0.05)[0]


def test_hidden_group_must_be_off_in_the_options(make_world):
    world = make_world(reference_scene(), camera=False)
    option = mujoco.MjvOption()
    option.geomgroup[5] = 1
    with pytest.raises(ValueError, match="group 5"):
        DrawOrder(world.model, option, 4 / 3)


@pytest.mark.parametrize("joint, offset_rad", [(None, 0.0), (0, 0.6), (3, -0.5), (5, 0.7), (6, 1.2)])
def test_culled_and_reordered_scene_renders_the_same_images(make_world, renderer_pair,
                                                           full_scene_passes, joint, offset_rad):
    world = make_world(reference_scene(), camera=False)
    if joint is not None:
        world.data.qpos[joint] += offset_rad
    mujoco.mj_forward(world.model, world.data)
    cam = world.model.camera(CAMERA_NAME).id
    groups = world.model.geom_group.copy()
    ours, theirs = renderer_pair(world.model, H, W)
    depth, colour, geoms = full_scene_passes(theirs, world.data, cam)
    full = theirs.scene.ngeom

    ours.update_scene(world.data, cam)
    assert np.array_equal(world.model.geom_group, groups)  # restored
    drawn = [ours.scene.geoms[i] for i in range(ours.scene.ngeom)]
    assert len(drawn) < full  # links out of view were left out
    plane = int(mujoco.mjtGeom.mjGEOM_PLANE)
    kinds = [int(g.type) == plane for g in drawn]
    assert kinds[-1] and kinds == sorted(kinds)  # the floor last
    z, rgb = ours.render(rgb=True)
    assert np.array_equal(z, depth) and np.array_equal(rgb, colour)
    assert np.array_equal(ours.segmentation(), geoms)
