"""The built-in set builds an object when it is first indexed, as a list of those objects would
hold it."""

import subprocess
import sys
import textwrap

import numpy as np
import pytest

from grasp_pipeline.objects.builtin import BUILTIN_NAMES, builtin_object
from grasp_pipeline.objects.builtin_set import BuiltinSet
from grasp_pipeline.objects.catalog import object_set


def _same_geometry(a, b) -> bool:
    return (a.name == b.name and len(a.parts) == len(b.parts)
            and all(np.array_equal(p.vertices, q.vertices) and np.array_equal(p.faces, q.faces)
                    for p, q in zip(a.parts, b.parts)))


def test_the_builtin_set_indexes_as_the_list_of_its_objects():
    objects = object_set("builtin")
    assert isinstance(objects, BuiltinSet)
    assert len(objects) == len(BUILTIN_NAMES) and objects.names == tuple(BUILTIN_NAMES)
    for k in (0, 7, len(objects) - 1):
        assert _same_geometry(objects[k], builtin_object(BUILTIN_NAMES[k]))
    assert objects[-1] is objects[len(objects) - 1]
    assert [m.name for m in objects[2:5]] == list(BUILTIN_NAMES[2:5])
    assert [m.name for m in objects] == list(BUILTIN_NAMES)
    with pytest.raises(IndexError):
        objects[len(objects)]


def test_each_set_holds_its_own_copies():
    first, second = object_set("builtin"), object_set("builtin")
    first[3].parts[0].vertices[:] += 1.0
    assert _same_geometry(second[3], builtin_object(BUILTIN_NAMES[3]))
    assert not _same_geometry(first[3], second[3])


def test_a_scene_builds_only_the_objects_it_draws():
    code = textwrap.dedent("""
        from grasp_pipeline.app.sim_system import SECTIONS, make_scene
        from grasp_pipeline.objects import builtin_set
        from grasp_pipeline.settings import load_settings
        settings = load_settings(SECTIONS)
        spec = make_scene("packed", 3, settings)
        print(len(builtin_set._BUILT), settings.clutter.objects_per_scene, len(spec.objects))
    """)
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    built, per_scene, placed = map(int, done.stdout.split())
    assert 1 <= built <= per_scene < len(BUILTIN_NAMES) and placed >= 1
