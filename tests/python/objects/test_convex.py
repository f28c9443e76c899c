"""Convex parts under bad input: a cached decomposition that does not fit its mesh (scaled,
another mesh's parts, malformed in every way) is named in a warning and recomputed, never used;
an open mesh collides as its hull with a warning, without a decomposition; mesh files too big to
load are refused before reading; the loader's warnings reach the log."""

from __future__ import annotations

import logging
import shutil
import time

import numpy as np
import pytest
import trimesh

from grasp_pipeline.objects import convex
from grasp_pipeline.objects.catalog import object_set
from grasp_pipeline.objects.convex import DecompositionParams, cache_key, hull_of
from grasp_pipeline.objects.mesh_object import load_mesh_object, load_object, read_mesh_bodies
from grasp_pipeline.objects.model import MeshError
from test_mesh_objects import l_prism

PARAMS = DecompositionParams(threshold=0.1, resolution=500, mcts_iterations=50, mcts_nodes=10)


def _mirrored_parts(mesh: trimesh.Trimesh) -> list:
    """The parts of the L mirrored in x: the same bounding box and volume, another shape."""
    arm = mesh.extents[0] / 2
    boxes = [trimesh.creation.box(bounds=[[0, 0, 0], [2 * arm, arm, mesh.extents[2]]]),
             trimesh.creation.box(bounds=[[arm, 0, 0], [2 * arm, 2 * arm, mesh.extents[2]]])]
    return [hull_of(b) for b in boxes]


@pytest.fixture(scope="module")
def good(tmp_path_factory):
    """(mesh, its cache file with a CoACD decomposition, the key)."""
    pytest.importorskip("coacd")
    cache = tmp_path_factory.mktemp("cache")
    mesh = l_prism()
    res = convex.decompose(mesh, PARAMS, cache_dir=cache)
    assert res.method == "coacd"
    key = cache_key(mesh, PARAMS)
    return mesh, cache / f"{key}.npz", key


def _corrupt(path, how: str, mesh):
    arrays = dict(np.load(path))
    if how == "truncated":
        path.write_bytes(path.read_bytes()[:200])
        return
    if how == "not an npz":
        path.write_text("hello")
        return
    if how == "another mesh (key)":
        convex._write_cache(path, _mirrored_parts(mesh), key="0" * 64)
        return
    if how == "another mesh (old file)":
        arrays = convex._pack(_mirrored_parts(mesh))
        arrays.pop("key")
    elif how == "25 % wider":
        arrays["vertices"] = arrays["vertices"] * [1.25, 1.0, 1.0]
    elif how == "x3":
        arrays["vertices"] = arrays["vertices"] * 3.0
    elif how == "faces out of range":
        arrays["faces"] = arrays["faces"] + 1000
    elif how == "counts do not add up":
        arrays["n_vertices"] = arrays["n_vertices"] + 5
    elif how == "negative counts":
        arrays["n_faces"] = -arrays["n_faces"]
    elif how == "nan vertices":
        arrays["vertices"][3] = np.nan
    elif how == "no faces":
        arrays.pop("faces")
    elif how == "object array":
        arrays["faces"] = np.array([None, 1], dtype=object)
    with path.open("wb") as fh:
        np.savez(fh, **arrays)


CORRUPTIONS = ["25 % wider", "x3", "another mesh (key)", "another mesh (old file)", "truncated",
               "not an npz", "faces out of range", "counts do not add up", "negative counts",
               "nan vertices", "no faces", "object array"]


@pytest.mark.parametrize("how", CORRUPTIONS)
def test_a_cache_file_that_does_not_fit_its_mesh_is_named_and_not_used(good, tmp_path, how):
    mesh, path, key = good
    bad = tmp_path / path.name
    shutil.copy(path, bad)
    _corrupt(bad, how, mesh)
    parts, problem = convex._read_cache(bad, mesh, key)
    assert parts is None and str(bad) in problem and problem.endswith("recomputed"), problem


def test_the_good_cache_file_and_an_old_one_without_key_are_used(good, tmp_path):
    mesh, path, key = good
    parts, problem = convex._read_cache(path, mesh, key)
    assert problem == "" and len(parts) >= 2
    old = tmp_path / path.name
    arrays = dict(np.load(path))
    arrays.pop("key")
    with old.open("wb") as fh:
        np.savez(fh, **arrays)
    assert convex._read_cache(old, mesh, key)[0] is not None


def test_a_bad_cache_is_recomputed_with_a_warning_on_the_object(good, tmp_path, caplog):
    mesh, path, key = good
    cache = tmp_path / "cache"
    cache.mkdir()
    shutil.copy(path, cache / path.name)
    _corrupt(cache / path.name, "25 % wider", mesh)
    obj_file = tmp_path / "ell.obj"
    mesh.export(obj_file)
    with caplog.at_level(logging.WARNING):
        obj = load_mesh_object(obj_file, cache_dir=cache, params=PARAMS)
    assert any(str(cache / path.name) in w and "does not fit its mesh" in w for w in obj.warnings)
    assert str(cache / path.name) in caplog.text
    assert obj.extents_m()[0] == pytest.approx(mesh.extents[0], rel=0.02)  # not 25 % wider
    again = load_mesh_object(obj_file, cache_dir=cache, params=PARAMS)  # rewritten: used again
    assert any("cached" in n for n in again.notes) and again.warnings == ()


def _bowl() -> trimesh.Trimesh:
    """An open hemisphere shell (no thickness), 8 cm wide: CoACD made thin shells of it for minutes."""
    s = trimesh.creation.icosphere(subdivisions=4, radius=0.04)
    bowl = trimesh.Trimesh(s.vertices, s.faces[s.triangles_center[:, 2] < 0.005])
    bowl.remove_unreferenced_vertices()
    return bowl


def test_an_open_mesh_collides_as_its_hull_with_a_warning_and_no_decomposition(tmp_path, monkeypatch):
    def no_coacd(*args, **kwargs):
        raise AssertionError("an open mesh must not be decomposed")

    monkeypatch.setattr(convex, "_run_coacd", no_coacd)
    path = tmp_path / "bowl.obj"
    _bowl().export(path)
    t0 = time.perf_counter()
    obj = load_mesh_object(path, cache_dir=tmp_path / "cache")
    assert time.perf_counter() - t0 < 5.0
    assert len(obj.parts) == 1 and obj.parts[0].is_convex
    assert any("open or non-manifold mesh" in w and "convex hull" in w for w in obj.warnings)
    assert any("visual mesh is not watertight" in w for w in obj.warnings)
    assert set(obj.warnings) <= set(obj.notes)


def test_a_small_hole_is_filled_and_the_body_decomposed(tmp_path):
    pytest.importorskip("coacd")
    ell = l_prism()
    ell.update_faces(np.arange(len(ell.faces)) != 3)  # one triangle of the top missing
    path = tmp_path / "holed_ell.obj"
    ell.export(path)
    obj = load_mesh_object(path, cache_dir=tmp_path / "cache", params=PARAMS)
    assert len(obj.parts) >= 2 and not any("open or non-manifold" in w for w in obj.warnings)


def test_mesh_and_urdf_files_over_the_limit_are_refused_before_reading(tmp_path):
    path = tmp_path / "huge.obj"
    with path.open("wb") as fh:  # 200 MB, sparse: reading it would take long, stat does not
        fh.truncate(200_000_000)
    t0 = time.perf_counter()
    with pytest.raises(MeshError, match=r"huge.obj: 200 MB is more than a mesh file may be \(32 MB\)"):
        read_mesh_bodies(path)
    urdf = tmp_path / "huge.urdf"
    with urdf.open("wb") as fh:
        fh.truncate(50_000_000)
    with pytest.raises(MeshError, match=r"huge.urdf: 50 MB is more than an object's URDF may be"):
        load_object(urdf)
    assert time.perf_counter() - t0 < 1.0


def test_the_loader_warnings_are_logged_when_a_set_loads(tmp_path, caplog):
    _bowl().export(tmp_path / "bowl.obj")
    trimesh.creation.box(extents=(0.03, 0.03, 0.03)).export(tmp_path / "cube.obj")
    with caplog.at_level(logging.INFO):
        models = object_set(tmp_path)
    assert [m.name for m in models] == ["bowl", "cube"]
    lines = [r.getMessage() for r in caplog.records if r.levelname == "WARNING"]
    assert any(line.startswith("object bowl (") and "open or non-manifold mesh" in line for line in lines)
    assert "loaded 2 objects" in caplog.text and "(1 with warnings)" in caplog.text
