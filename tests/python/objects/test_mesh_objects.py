"""Objects from mesh files: OBJ/STL, VGN/GIGA URDF folders, convex parts (CoACD, cached), frame,
scale and every kind of bad input (MeshError naming the file). All files are made in tmp_path."""

from __future__ import annotations

import sys
import time
import warnings

import numpy as np
import pytest
import trimesh

from grasp_pipeline.objects import convex
from grasp_pipeline.objects.convex import DecompositionParams, convex_parts
from grasp_pipeline.objects.mesh_object import (MAX_EXTENT_M, MIN_EXTENT_M, load_mesh_object,
                                                load_object, load_object_dir, load_objects,
                                                load_urdf_object)
from grasp_pipeline.objects.model import MeshError

URDF = """<?xml version="1.0"?>
<robot name="{name}">
  <link name="base_link">
    <inertial><mass value="0.05"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
    <visual>{vorigin}<geometry><mesh filename="{visual}"{scale}/></geometry></visual>
    <collision>{corigin}<geometry><mesh filename="{collision}"{scale}/></geometry></collision>
  </link>
</robot>
"""


def box(extents, centre=(0.0, 0.0, 0.0)) -> trimesh.Trimesh:
    m = trimesh.creation.box(extents=extents)
    m.apply_translation(centre)
    return m


def l_prism(arm=0.05, height=0.03) -> trimesh.Trimesh:
    """A closed L-shaped prism (one non-convex body), built face by face."""
    poly = np.array([(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)], float) * arm / 2
    tris = [(0, 1, 2), (0, 2, 3), (0, 3, 4), (0, 4, 5)]
    n = len(poly)
    verts = np.vstack([np.c_[poly, np.zeros(n)], np.c_[poly, np.full(n, height)]])
    faces = [(c, b, a) for a, b, c in tris] + [(a + n, b + n, c + n) for a, b, c in tris]
    for i in range(n):
        j = (i + 1) % n
        faces += [(i, j, j + n), (i, j + n, i + n)]
    return trimesh.Trimesh(verts, faces)


def write_groups_obj(path, meshes, names=None):
    """An OBJ with one ``o`` group per mesh (VGN's decomposed collision layout)."""
    lines, base = [], 1
    for k, m in enumerate(meshes):
        lines.append(f"o {names[k] if names else f'convex_{k}'}")
        lines += [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in m.vertices]
        lines += [f"f {a + base} {b + base} {c + base}" for a, b, c in m.faces]
        base += len(m.vertices)
    path.write_text("\n".join(lines) + "\n")
    return path


def write_urdf(folder, name, visual, collision, *, scale=None, origin="", collision_origin=None):
    scale_attr = f' scale="{scale}"' if scale else ""
    corigin = origin if collision_origin is None else collision_origin
    path = folder / f"{name}.urdf"
    path.write_text(URDF.format(name=name, visual=visual, collision=collision, scale=scale_attr,
                                vorigin=origin, corigin=corigin))
    return path


def vgn_object(folder, name, parts):
    """URDF + visual OBJ + collision OBJ (one group per part), VGN/GIGA style."""
    trimesh.util.concatenate(parts).export(folder / f"{name}_visual.obj")
    write_groups_obj(folder / f"{name}_collision.obj", parts)
    return write_urdf(folder, name, f"{name}_visual.obj", f"{name}_collision.obj")


def assert_standing_centred(obj):
    lo, hi = obj.bounds_m()
    assert lo[2] == pytest.approx(0.0, abs=1e-9)
    assert (lo[:2] + hi[:2]) == pytest.approx([0.0, 0.0], abs=1e-9)


@pytest.fixture
def cache(tmp_path):
    return tmp_path / "cache"


# ----------------------------------------------------------------------------------- files


def test_obj_file_is_one_convex_part_standing_on_z0(tmp_path, cache):
    path = tmp_path / "brick.obj"
    box((0.04, 0.06, 0.02), centre=(0.3, -0.2, 0.5)).export(path)
    obj = load_mesh_object(path, cache_dir=cache)
    assert obj.name == "brick" and obj.source == str(path)
    assert len(obj.parts) == 1 and obj.parts[0].is_convex
    assert obj.extents_m() == pytest.approx([0.04, 0.06, 0.02], abs=1e-9)
    assert_standing_centred(obj)
    assert obj.visual.bounds == pytest.approx(obj.bounds_m(), abs=1e-9)  # same transform
    assert obj.volume_m3() == pytest.approx(0.04 * 0.06 * 0.02, rel=1e-6)
    assert obj.mass_kg(1000.0) == pytest.approx(0.048, rel=1e-6)


def test_stl_file_loads_with_name_colour_and_scale(tmp_path, cache):
    path = tmp_path / "can.stl"
    trimesh.creation.cylinder(radius=0.02, height=0.1, sections=24).export(path)
    obj = load_mesh_object(path, name="soup", rgba=(1, 0, 0, 1), cache_dir=cache, scale=0.5)
    assert (obj.name, obj.rgba) == ("soup", (1.0, 0.0, 0.0, 1.0))
    assert len(obj.parts) == 1
    assert obj.extents_m()[2] == pytest.approx(0.05, abs=1e-9)
    assert obj.extents_m()[0] == pytest.approx(0.02, abs=1e-3)
    assert_standing_centred(obj)
    assert obj.volume_m3() == pytest.approx(obj.visual.volume, rel=1e-9) and obj.visual.volume > 0


def test_scale_multiplies_extents_and_volume(tmp_path, cache):
    path = tmp_path / "cube.obj"
    box((0.03, 0.03, 0.03)).export(path)
    one, two = (load_mesh_object(path, scale=s, cache_dir=cache) for s in (1.0, 2.0))
    assert two.extents_m() == pytest.approx(2 * one.extents_m())
    assert two.volume_m3() == pytest.approx(8 * one.volume_m3())
    assert_standing_centred(two)


def test_load_object_dispatches_on_the_path(tmp_path, cache):
    obj_file = tmp_path / "a.obj"
    box((0.02, 0.02, 0.02)).export(obj_file)
    single = tmp_path / "single"
    single.mkdir()
    vgn_object(single, "thing", [box((0.02, 0.03, 0.04))])
    assert load_object(obj_file, cache_dir=cache).name == "a"
    assert load_object(single, cache_dir=cache).name == "thing"
    assert load_object(single / "thing.urdf", cache_dir=cache).name == "thing"
    assert [o.name for o in load_objects(single, cache_dir=cache)] == ["thing"]


# ----------------------------------------------------------------------------------- URDF


def test_vgn_folder_keeps_each_collision_group_as_a_part(tmp_path, cache):
    # a table-like object: a top and four legs, five bodies in the collision OBJ
    legs = [box((0.01, 0.01, 0.05), (x, y, 0.025)) for x in (-0.04, 0.04) for y in (-0.03, 0.03)]
    table = [box((0.1, 0.08, 0.01), (0, 0, 0.055))] + legs
    vgn_object(tmp_path, "zeta_table", table)
    vgn_object(tmp_path, "alpha_block", [box((0.03, 0.03, 0.03))])
    (tmp_path / "notes.txt").write_text("not an object")
    objs = load_object_dir(tmp_path, cache_dir=cache)
    assert [o.name for o in objs] == ["alpha_block", "zeta_table"]  # sorted, deterministic
    block, tab = objs
    assert len(block.parts) == 1 and len(tab.parts) == 5
    assert all(p.is_convex and p.volume > 0 for p in tab.parts)
    assert tab.extents_m() == pytest.approx([0.1, 0.08, 0.06], abs=1e-6)
    assert tab.volume_m3() == pytest.approx(0.1 * 0.08 * 0.01 + 4 * 0.01 * 0.01 * 0.05, rel=1e-6)
    assert_standing_centred(tab)
    assert tab.source == str(tmp_path / "zeta_table.urdf")
    assert [o.name for o in load_object_dir(tmp_path, cache_dir=cache)] == ["alpha_block", "zeta_table"]


def test_urdf_scale_and_origin_move_visual_and_collision_together(tmp_path, cache):
    box((0.02, 0.04, 0.06)).export(tmp_path / "v.obj")
    write_groups_obj(tmp_path / "c.obj", [box((0.02, 0.04, 0.06))])
    # rotate 90 degrees about x: the y and z extents swap; scale 0.5 in x
    write_urdf(tmp_path, "rot", "v.obj", "c.obj", scale="0.5 1 1",
               origin='<origin xyz="0.1 0.2 0.3" rpy="1.5707963267948966 0 0"/>')
    obj = load_urdf_object(tmp_path / "rot.urdf", cache_dir=cache)
    assert obj.extents_m() == pytest.approx([0.01, 0.06, 0.04], abs=1e-9)
    assert obj.visual.bounds == pytest.approx(obj.bounds_m(), abs=1e-9)
    assert_standing_centred(obj)


def test_urdf_primitives_and_material_colour(tmp_path, cache):
    (tmp_path / "cyl.urdf").write_text(
        '<robot name="cyl"><link name="l"><visual><geometry><cylinder radius="0.015" length="0.06"/>'
        '</geometry><material name="red"><color rgba="1 0 0 1"/></material></visual>'
        '<collision><geometry><cylinder radius="0.015" length="0.06"/></geometry></collision>'
        '</link></robot>')
    obj = load_urdf_object(tmp_path / "cyl.urdf", cache_dir=cache)
    assert obj.rgba == (1.0, 0.0, 0.0, 1.0) and len(obj.parts) == 1
    assert obj.extents_m() == pytest.approx([0.03, 0.03, 0.06], abs=1e-4)
    assert_standing_centred(obj)


def test_many_bodies_are_limited_and_tiny_ones_dropped(tmp_path, cache):
    cubes = [box((0.01, 0.01, 0.01), (0.012 * i, 0.012 * j, 0.0)) for i in range(6) for j in range(7)]
    cubes.append(box((1e-4, 1e-4, 1e-4), (0.0, 0.1, 0.0)))  # a speck far from the rest
    path = write_groups_obj(tmp_path / "grid.obj", cubes)
    obj = load_mesh_object(path, cache_dir=cache)
    assert len(obj.parts) == convex.MAX_PARTS
    assert all(p.is_convex and p.volume > 0 for p in obj.parts)
    assert any("dropped 1 tiny" in n for n in obj.notes) and any("merged" in n for n in obj.notes)
    assert obj.extents_m()[1] == pytest.approx(0.01 + 6 * 0.012, abs=1e-6)  # speck is gone


# ----------------------------------------------------------------------------------- coacd


def test_non_convex_body_is_decomposed_by_coacd_and_cached(tmp_path, cache):
    pytest.importorskip("coacd")
    path = tmp_path / "ell.obj"
    l_prism().export(path)
    params = DecompositionParams(threshold=0.1, resolution=500, mcts_iterations=50, mcts_nodes=10)
    t0 = time.perf_counter()
    first = load_mesh_object(path, cache_dir=cache, params=params)
    t_first = time.perf_counter() - t0
    assert len(first.parts) > 1 and all(p.is_convex and p.volume > 0 for p in first.parts)
    assert sum(p.volume for p in first.parts) == pytest.approx(l_prism().volume, rel=0.05)
    assert len(list(cache.glob("*.npz"))) == 1
    t0 = time.perf_counter()
    second = load_mesh_object(path, cache_dir=cache, params=params)
    t_second = time.perf_counter() - t0
    assert any("cached" in n for n in second.notes)
    assert t_second < t_first
    assert len(second.parts) == len(first.parts)
    for a, b in zip(first.parts, second.parts):
        assert np.array_equal(a.vertices, b.vertices) and np.array_equal(a.faces, b.faces)
    # other parameters are another cache entry
    convex_parts([l_prism()], DecompositionParams(threshold=0.2, resolution=500, mcts_iterations=50,
                                                  mcts_nodes=10), cache_dir=cache)
    assert len(list(cache.glob("*.npz"))) == 2


def test_default_cache_is_under_home_and_a_corrupt_entry_is_recomputed(tmp_path, monkeypatch):
    pytest.importorskip("coacd")
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    path = tmp_path / "ell.obj"
    l_prism().export(path)
    params = DecompositionParams(threshold=0.1, resolution=500, mcts_iterations=50, mcts_nodes=10)
    first = load_mesh_object(path, params=params)
    entries = list((tmp_path / "home" / ".cache" / "grasp_pipeline" / "convex").glob("*.npz"))
    assert len(entries) == 1
    entries[0].write_bytes(b"not an npz")
    again = load_mesh_object(path, params=params)
    assert not any("cached" in n for n in again.notes)  # recomputed, not read
    assert [p.vertices.tolist() for p in again.parts] == [p.vertices.tolist() for p in first.parts]
    assert any("cached" in n for n in load_mesh_object(path, params=params).notes)


def test_without_coacd_a_single_hull_and_one_warning(tmp_path, cache, monkeypatch):
    monkeypatch.setitem(sys.modules, "coacd", None)  # import coacd -> ImportError
    monkeypatch.setattr(convex, "_warned_no_coacd", False)
    path = tmp_path / "ell.obj"
    l_prism().export(path)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        first = load_mesh_object(path, cache_dir=cache)
        second = load_mesh_object(path, cache_dir=cache)
    msgs = [str(w.message) for w in caught if "coacd" in str(w.message)]
    assert len(msgs) == 1 and "pip install '.[meshes]'" in msgs[0]
    for obj in (first, second):
        assert len(obj.parts) == 1 and obj.parts[0].is_convex
        assert obj.parts[0].volume == pytest.approx(l_prism().convex_hull.volume, rel=1e-6)
        assert any("coacd is not installed" in n for n in obj.notes)
    assert not cache.exists() or not list(cache.glob("*.npz"))  # a hull is not a decomposition


# ----------------------------------------------------------------------------------- errors


def error_for(tmp_path, load, *args, **kwargs) -> str:
    with pytest.raises(MeshError) as info:
        load(*args, cache_dir=tmp_path / "cache", **kwargs)
    msg = str(info.value)
    assert msg.isascii(), msg
    return msg


def test_missing_files_are_named(tmp_path):
    msg = error_for(tmp_path, load_mesh_object, tmp_path / "nope.obj")
    assert "nope.obj" in msg and "not found" in msg
    box((0.02, 0.02, 0.02)).export(tmp_path / "v.obj")
    urdf = write_urdf(tmp_path, "broken", "v.obj", "meshes/gone_collision.obj")
    msg = error_for(tmp_path, load_urdf_object, urdf)
    assert "broken.urdf" in msg and "gone_collision.obj" in msg and "does not exist" in msg
    msg = error_for(tmp_path, load_object, tmp_path / "absent.urdf")
    assert "absent.urdf" in msg and "not found" in msg


@pytest.mark.parametrize("name, text, expected", [
    ("empty.obj", "", "empty"),
    ("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no triangles"),
    ("words.stl", "this is not an STL file\n", "no triangles"),
    ("nan.obj", "v 0 0 0\nv 0.01 0 0\nv 0 nan 0\nv 0 0 0.01\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n",
     "not finite"),
    ("badindex.obj", "v 0 0 0\nv 0.01 0 0\nv 0 0.01 0\nf 1 2 9\n", "cannot be read"),
    ("mesh.ply", "ply\n", "not a mesh file"),
    ("mesh.txt", "hello\n", "not a mesh file"),
])
def test_bad_mesh_files_are_named(tmp_path, name, text, expected):
    (tmp_path / name).write_text(text)
    msg = error_for(tmp_path, load_object, tmp_path / name)
    assert name in msg and expected in msg


@pytest.mark.parametrize("extent, scale, expected", [
    (0.004, 1.0, "absurd size"), (1.5, 1.0, "millimetres"), (0.3, 5.0, "absurd size"),
    (0.01, 0.1, "absurd size"),
])
def test_absurd_sizes_are_refused(tmp_path, extent, scale, expected):
    path = tmp_path / "odd.stl"
    box((extent, extent / 2, extent / 2)).export(path)
    msg = error_for(tmp_path, load_mesh_object, path, scale=scale)
    assert "odd.stl" in msg and expected in msg
    assert f"{MIN_EXTENT_M:g}" in msg and f"{MAX_EXTENT_M:g}" in msg


def test_flat_mesh_has_no_collision_part(tmp_path):
    path = tmp_path / "sheet.obj"
    path.write_text("v 0 0 0\nv 0.05 0 0\nv 0.05 0.05 0\nv 0 0.05 0\nf 1 2 3\nf 1 3 4\n")
    msg = error_for(tmp_path, load_mesh_object, path)
    assert "sheet.obj" in msg and "positive volume" in msg


@pytest.mark.parametrize("text, expected", [
    ("<robot name='x'><link name='l'><visual><geometry>", "not well-formed XML"),
    ("<robot name='x'><link name='l'><inertial><mass value='1'/></inertial></link></robot>",
     "has no mesh"),
    ("<sdf version='1.6'/>", "not a URDF"),
    ("<robot name='x'><link name='a'/><link name='b'/></robot>", "exactly one <link>"),
    ("<robot name='x'><link name='l'><visual><geometry><mesh/></geometry></visual></link></robot>",
     "no filename"),
    ("<robot name='x'><link name='l'><visual><geometry><box size='1 2'/></geometry></visual>"
     "</link></robot>", "3 finite numbers"),
])
def test_bad_urdfs_are_named(tmp_path, text, expected):
    path = tmp_path / "bad.urdf"
    path.write_text(text)
    msg = error_for(tmp_path, load_urdf_object, path)
    assert "bad.urdf" in msg and expected in msg


def test_bad_arguments_and_folders(tmp_path):
    path = tmp_path / "c.obj"
    box((0.02, 0.02, 0.02)).export(path)
    assert "scale" in error_for(tmp_path, load_mesh_object, path, scale=0)
    assert "rgba" in error_for(tmp_path, load_mesh_object, path, rgba=(2, 0, 0, 1))
    empty = tmp_path / "empty_dir"
    empty.mkdir()
    assert "empty_dir" in error_for(tmp_path, load_object_dir, empty)
    assert "missing_dir" in error_for(tmp_path, load_object_dir, tmp_path / "missing_dir")


def test_a_bad_object_in_a_folder_raises_or_is_skipped(tmp_path, cache):
    vgn_object(tmp_path, "good", [box((0.02, 0.02, 0.02))])
    (tmp_path / "worse.urdf").write_text("<robot")
    with pytest.raises(MeshError, match="worse.urdf"):
        load_object_dir(tmp_path, cache_dir=cache)
    assert [o.name for o in load_object_dir(tmp_path, cache_dir=cache, skip_bad=True)] == ["good"]


def test_open_visual_is_allowed_with_a_note(tmp_path, cache):
    open_box = box((0.03, 0.03, 0.03))
    open_box.update_faces(np.arange(len(open_box.faces)) != 0)  # one triangle missing
    open_box.export(tmp_path / "v.obj")
    write_groups_obj(tmp_path / "c.obj", [box((0.03, 0.03, 0.03))])
    obj = load_urdf_object(write_urdf(tmp_path, "open", "v.obj", "c.obj"), cache_dir=cache)
    assert not obj.visual.is_watertight and any("not watertight" in n for n in obj.notes)
    assert obj.volume_m3() == pytest.approx(0.03 ** 3, rel=1e-6)  # from the parts
