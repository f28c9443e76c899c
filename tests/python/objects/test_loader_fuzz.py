"""Hypothesis fuzz of the object loader (``--objects``: OBJ, STL, URDF files) over the full range:
vertices from subnormals to float64's largest, NaN and infinities, faces with indices out of
range, negative or repeated, garbage lines, several groups, a closed non-convex L block (CoACD)
scaled and jittered or with faces missing, binary STL with any bytes, URDFs
with any numbers in their attributes and references to such meshes.

The invariant: :func:`load_object` returns an object whose parts are convex, finite, of positive
volume and of a household size, or raises a MeshError naming the file — nothing else, quickly.
CI runs GRASP_FUZZ_EXAMPLES examples (default 25 per test, a few seconds); a long run:

    GRASP_FUZZ_EXAMPLES=5000 PYTHONPATH=python .venv/bin/python -m pytest -q \\
        tests/python/objects/test_loader_fuzz.py --hypothesis-show-statistics
"""

from __future__ import annotations

import os
import struct

import numpy as np
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from grasp_pipeline.objects.convex import DecompositionParams
from grasp_pipeline.objects.mesh_object import MAX_EXTENT_M, MIN_EXTENT_M, load_object
from grasp_pipeline.objects.model import MeshError
from test_mesh_objects import l_prism

EXAMPLES = int(os.environ.get("GRASP_FUZZ_EXAMPLES", "25"))
FUZZ = settings(max_examples=EXAMPLES, deadline=None, derandomize=not os.environ.get("GRASP_FUZZ_RANDOM"),
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture,
                                       HealthCheck.data_too_large])
#: Quick decompositions (a closed non-convex random mesh is rare, but it is decomposed).
PARAMS = DecompositionParams(threshold=0.2, resolution=300, mcts_iterations=20, mcts_nodes=5)

F64 = np.finfo(np.float64)
EDGE_VALUES = [0.0, -0.0, 5e-324, 1e-300, float(F64.max), -float(F64.max), float("nan"), float("inf"), -float("inf"),
           1e30, -1e30, 0.001, 0.05, -0.05, 0.5, 1.0, 2.0, 1000.0]
coord = st.one_of(st.sampled_from(EDGE_VALUES), st.floats(allow_nan=True, allow_infinity=True),
                  st.floats(-0.1, 0.1), st.floats(-0.06, 0.06))
vertex = st.tuples(coord, coord, coord)
index = st.one_of(st.integers(-20, 40), st.sampled_from([0, -1, 2**31, -(2**63), 10**20]))


@st.composite
def l_block_text(draw) -> str:
    """The closed L prism of the mesh tests (decomposed by CoACD), scaled, jittered, with faces
    missing (open: collides as its hull) or repeated."""
    mesh = l_prism(arm=draw(st.sampled_from([0.05, 0.002, 0.3, 3.0])), height=draw(st.floats(1e-4, 0.2)))
    v = mesh.vertices + np.array(draw(st.lists(st.floats(-0.003, 0.003), min_size=3 * len(mesh.vertices),
                                               max_size=3 * len(mesh.vertices)))).reshape(-1, 3)
    drop = draw(st.sets(st.integers(0, len(mesh.faces) - 1), max_size=3))
    faces = [f for i, f in enumerate(mesh.faces) if i not in drop] + draw(st.lists(st.sampled_from(list(mesh.faces)), max_size=2))
    return "\n".join([f"v {float(x)!r} {float(y)!r} {float(z)!r}" for x, y, z in v]
                     + [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces]) + "\n"


@st.composite
def obj_text(draw) -> str:
    if draw(st.integers(0, 5)) == 0:
        return draw(l_block_text())
    lines = []
    for g in range(draw(st.integers(1, 3))):
        if draw(st.booleans()):
            lines.append(f"o part{g}")
        box = draw(st.booleans())
        verts = (draw(st.lists(vertex, min_size=0, max_size=24)) if not box else
                 [(x * s, y * s, z * s) for x in (0, 1) for y in (0, 1) for z in (0, 1)
                  for s in [draw(st.sampled_from([0.03, 0.001, 5.0, float("nan")]))]])
        lines += [f"v {x!r} {y!r} {z!r}" for x, y, z in verts]
        n_faces = draw(st.integers(0, 30))
        lines += [f"f {a} {b} {c}" for a, b, c in draw(st.lists(st.tuples(index, index, index),
                                                                min_size=n_faces, max_size=n_faces))]
        lines += draw(st.lists(st.text(max_size=30), max_size=3))
    return "\n".join(lines) + "\n"


@st.composite
def binary_stl(draw) -> bytes:
    tris = draw(st.lists(st.tuples(vertex, vertex, vertex), max_size=16))
    claimed = draw(st.one_of(st.just(len(tris)), st.integers(0, 2**32 - 1)))
    with np.errstate(over="ignore"):
        rows = np.array(tris, dtype=np.float64).reshape(-1, 9).astype(np.float32)
    body = b"".join(struct.pack("<3f", 0, 0, 0) + row.tobytes() + b"\0\0" for row in rows)
    return b"\0" * 80 + struct.pack("<I", claimed) + body


def _check(path) -> None:
    try:
        obj = load_object(path, cache_dir=path.parent / "cache", params=PARAMS)
    except MeshError as exc:
        msg = str(exc)
        assert path.name in msg and "\n" not in msg, msg
        event("refused: " + msg.split(": ", 1)[-1][:24])
        return
    event(f"loaded: {'several parts' if len(obj.parts) > 1 else 'one part'}"
          + (", with warnings" if obj.warnings else ""))
    assert obj.parts
    for p in obj.parts:
        assert np.isfinite(p.vertices).all() and p.volume > 0 and p.is_convex
    assert MIN_EXTENT_M <= float(np.max(obj.extents_m())) <= MAX_EXTENT_M * 1.0001


@FUZZ
@given(text=obj_text())
def test_any_obj_file_loads_or_is_refused_naming_it(tmp_path_factory, text):
    path = tmp_path_factory.mktemp("obj") / "fuzz.obj"
    path.write_text(text)
    _check(path)


@FUZZ
@given(data=st.one_of(binary_stl(), st.binary(max_size=400)))
def test_any_stl_file_loads_or_is_refused_naming_it(tmp_path_factory, data):
    path = tmp_path_factory.mktemp("stl") / "fuzz.stl"
    path.write_bytes(data)
    _check(path)


NUMBER_TEXT = st.one_of(coord.map(repr), st.text(alphabet="0123456789.-+eE naif", max_size=12))


@FUZZ
@given(text=obj_text(), scale=NUMBER_TEXT, size=NUMBER_TEXT, rpy=NUMBER_TEXT, rgba=NUMBER_TEXT,
       kind=st.sampled_from(["mesh", "box", "cylinder", "sphere", "capsule", ""]))
def test_any_urdf_loads_or_is_refused_naming_it(tmp_path_factory, text, scale, size, rpy, rgba, kind):
    folder = tmp_path_factory.mktemp("urdf")
    (folder / "m.obj").write_text(text)
    shape = {"mesh": f'<mesh filename="m.obj" scale="{scale} {scale} {scale}"/>',
             "box": f'<box size="{size} {size} {size}"/>', "cylinder": f'<cylinder radius="{size}" length="{scale}"/>',
             "sphere": f'<sphere radius="{size}"/>', "capsule": '<capsule radius="0.1" length="0.2"/>', "": ""}[kind]
    path = folder / "o.urdf"
    path.write_text(f'<?xml version="1.0"?><robot name="o"><link name="l"><visual><origin xyz="0 0 0" '
                    f'rpy="{rpy} 0 0"/><geometry>{shape}</geometry><material name="c"><color rgba="{rgba} 0 0 1"/>'
                    f'</material></visual><collision><geometry>{shape}</geometry></collision></link></robot>')
    _check(path)
