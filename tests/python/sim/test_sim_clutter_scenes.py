"""Packed and pile scenes (VGN/GIGA protocols): deterministic, inside the square, no object
placed touching another (packed), dropped into a box that is then removed (pile)."""

import numpy as np
import pytest
import trimesh

from grasp_pipeline.objects.model import ObjectModel
from grasp_pipeline.sim.clutter_config import ClutterConfig
from grasp_pipeline.sim.clutter_scenes import packed_scene, pile_scene
from grasp_pipeline.sim.config import load_sim_config
from grasp_pipeline.sim.work_cell import table_top_z_m
from grasp_pipeline.sim.world import SimWorld

SIM = load_sim_config()
CFG = ClutterConfig(settle_s=0.8)


def _model(name, mesh) -> ObjectModel:
    mesh.apply_translation((0.0, 0.0, -mesh.bounds[0][2]))
    return ObjectModel(name, (mesh,), (0.3, 0.5, 0.8, 1.0), name, visual=mesh, source="test")


MODELS = [_model("box", trimesh.creation.box((0.05, 0.07, 0.06))),
          _model("can", trimesh.creation.cylinder(radius=0.03, height=0.09, sections=24)),
          _model("flat", trimesh.creation.box((0.04, 0.10, 0.03)))]


def _inside_square(scene):
    c = np.asarray(CFG.square_center_m)
    return all(np.all(np.abs(np.asarray(o.position_m[:2]) - c) <= CFG.square_size_m / 2) for o in scene.objects)


def _object_contacts(scene) -> int:
    with SimWorld(scene, camera=False) as w:
        import mujoco

        mujoco.mj_forward(w.model, w.data)
        n = 0
        for i in range(w.data.ncon):
            c = w.data.contact[i]
            n1, n2 = w.geom_name(c.geom1), w.geom_name(c.geom2)
            n += n1.startswith("obj_") and n2.startswith("obj_")
        return n


def test_packed_scenes_are_deterministic_upright_and_not_touching():
    a, b = packed_scene(MODELS, 3, CFG, SIM), packed_scene(MODELS, 3, CFG, SIM)
    assert [o.position_m for o in a.objects] == [o.position_m for o in b.objects]
    assert len(a.objects) + len(a.notes) == CFG.objects_per_scene
    assert len(a.objects) >= 3 and _inside_square(a)
    assert _object_contacts(a) == 0
    for o in a.objects:  # upright on the table
        assert o.position_m[2] == pytest.approx(table_top_z_m() + o.size_m[2] / 2, abs=1e-3)
    assert packed_scene(MODELS, 4, CFG, SIM).objects[0].position_m != a.objects[0].position_m


def test_pile_scenes_settle_inside_the_square_and_are_deterministic():
    a = pile_scene(MODELS, 5, CFG, SIM)
    b = pile_scene(MODELS, 5, CFG, SIM)
    assert [o.position_m for o in a.objects] == [o.position_m for o in b.objects]
    assert a.objects and _inside_square(a)
    assert all(o.quat_wxyz is not None for o in a.objects)
    with SimWorld(a, camera=False) as w:  # the pile stays where it came to rest
        start = np.array([w.data.xpos[w.model.body("obj_" + o.name).id] for o in a.objects])
        w.run_until(w.time_s + 0.5)
        end = np.array([w.data.xpos[w.model.body("obj_" + o.name).id] for o in a.objects])
    assert np.max(np.linalg.norm(end - start, axis=1)) < 0.01
