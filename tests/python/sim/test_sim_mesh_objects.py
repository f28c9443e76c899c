"""Mesh objects in the world: convex parts collide and carry the mass, the visual mesh is
what the camera sees, the body frame is the bounding-box centre like the primitives'."""

import dataclasses

import numpy as np
import pytest
import trimesh

from grasp_pipeline.objects.model import ObjectModel
from grasp_pipeline.sim.ground_truth import object_truths
from grasp_pipeline.sim.scene_spec import ObjectSpec
from grasp_pipeline.sim.scenes import reference_scene
from grasp_pipeline.sim.world import SimWorld

TABLE_Z = 0.2


def l_block() -> ObjectModel:
    """An L of two boxes (4 x 8 x 3 cm and 4 x 4 x 3 cm), standing on z = 0."""
    a = trimesh.creation.box((0.04, 0.08, 0.03))
    a.apply_translation((0.0, 0.0, 0.015))
    b = trimesh.creation.box((0.04, 0.04, 0.03))
    b.apply_translation((0.04, 0.02, 0.015))
    return ObjectModel("l_block", (a, b), (0.9, 0.5, 0.1, 1.0), "L block",
                       visual=trimesh.util.concatenate([a, b]), source="test")


@pytest.fixture(scope="module")
def world():
    model = l_block()
    ext = model.extents_m()
    obj = ObjectSpec("l_block", "mesh", tuple(float(e) for e in ext),
                     (0.45, 0.15, TABLE_Z + 0.5 * ext[2] + 0.0005), rgba=model.rgba, mesh=model)
    ref = reference_scene()
    w = SimWorld(dataclasses.replace(ref, objects=ref.objects + (obj,)))
    yield w
    w.close()


def test_a_mesh_object_rests_on_the_table_with_the_mass_of_its_parts(world):
    m = world.model
    bid = m.body("obj_l_block").id
    volume = 0.04 * 0.08 * 0.03 + 0.04 * 0.04 * 0.03
    assert m.body_mass[bid] == pytest.approx(volume * world.config.object_density_kg_m3, rel=1e-6)
    world.run_until(world.time_s + 1.0)
    truth = next(t for t in object_truths(world) if t.name == "l_block")
    assert truth.position_m[2] == pytest.approx(TABLE_Z + 0.015, abs=2e-3)  # no sinking, no tipping


def test_the_camera_sees_the_visual_mesh_and_contacts_use_the_parts(world):
    names = [world.model.geom(g).name for g in range(world.model.ngeom)]
    assert {"obj_l_block_p0", "obj_l_block_p1", "obj_l_block_visual"} <= set(names)
    g = world.model.geom("obj_l_block_visual").id
    assert world.model.geom_contype[g] == 0 and world.model.geom_group[g] == 2
    frame = world.capture()
    pts = frame.points_world[np.isfinite(frame.points_world[:, 0])]
    near = pts[np.linalg.norm(pts[:, :2] - [0.45, 0.15], axis=1) < 0.04]
    top = near[near[:, 2] > TABLE_Z + 0.02, 2]  # the L's top face (3 cm), 2 mm depth noise
    assert len(top) > 200 and float(np.median(top)) == pytest.approx(TABLE_Z + 0.03, abs=2e-3)
