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
