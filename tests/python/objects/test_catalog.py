"""Object sets by name: the built-in set, a folder of meshes, errors naming the path."""

import pytest
import trimesh

from grasp_pipeline.objects.catalog import object_set
from grasp_pipeline.objects.model import MeshError


def test_builtin_is_the_shipped_set():
    names = [m.name for m in object_set("builtin")]
    assert len(names) >= 30 and len(set(names)) == len(names)


def test_a_folder_of_meshes_is_a_set(tmp_path):
    trimesh.creation.box((0.05, 0.04, 0.03)).export(tmp_path / "brick.obj")
    trimesh.creation.cylinder(radius=0.03, height=0.08).export(tmp_path / "can.stl")
    models = object_set(tmp_path)
    assert sorted(m.name for m in models) == ["brick", "can"]


def test_a_missing_set_names_the_path(tmp_path):
    with pytest.raises(MeshError, match="nope"):
        object_set(tmp_path / "nope")


def test_a_set_is_loaded_once_and_each_call_gets_its_own_copies(tmp_path, monkeypatch):
    import grasp_pipeline.objects.catalog as catalog

    trimesh.creation.box((0.05, 0.04, 0.03)).export(tmp_path / "brick.obj")
    loads = []
    real_load = catalog._load
    monkeypatch.setattr(catalog, "_load", lambda src: loads.append(src) or real_load(src))
    first = object_set(tmp_path)
    first[0].parts[0].vertices += 1.0  # a caller changing its models changes nobody else's
    second = object_set(tmp_path)
    assert len(loads) == 1 and second[0].parts[0].vertices.max() < 0.1
    assert second[0] is not first[0]


def test_a_changed_folder_is_loaded_again(tmp_path):
    trimesh.creation.box((0.05, 0.04, 0.03)).export(tmp_path / "brick.obj")
    assert [m.name for m in object_set(tmp_path)] == ["brick"]
    trimesh.creation.cylinder(radius=0.03, height=0.08).export(tmp_path / "can.stl")
    assert sorted(m.name for m in object_set(tmp_path)) == ["brick", "can"]
    trimesh.creation.box((0.08, 0.04, 0.03)).export(tmp_path / "brick.obj")  # another size
    bricks = [m for m in object_set(tmp_path) if m.name == "brick"]
    assert bricks[0].parts[0].extents.max() > 0.07
