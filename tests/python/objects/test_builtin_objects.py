"""The built-in object set: convex watertight parts, standing on z = 0, household-sized,
graspable across one side by the 8 cm gripper, deterministic, named and coloured."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh

from grasp_pipeline.objects.builtin import (BUILTIN_NAMES, COLORS, builtin_object,
                                            builtin_objects, footprint_min_width_m)
from grasp_pipeline.objects.model import MeshError, ObjectModel

#: The gripper opens 8 cm; leave 1 cm of clearance for the approach.
MAX_GRASP_WIDTH_M = 0.07
MIN_GRASP_WIDTH_M = 0.01
FAMILIES = {"cube", "cuboid", "cylinder", "triangular_prism", "circular_segment", "bottle",
            "can", "mug", "bowl", "l_block", "t_block", "cross_block", "rounded_box", "blob"}
OBJECTS = builtin_objects()
IDS = [o.name for o in OBJECTS]


def test_at_least_30_objects_with_unique_names():
    assert len(BUILTIN_NAMES) >= 30
    assert len(set(BUILTIN_NAMES)) == len(BUILTIN_NAMES)
    assert [o.name for o in OBJECTS] == list(BUILTIN_NAMES)


def test_categories_cover_every_family():
    assert {o.category for o in OBJECTS} == FAMILIES


@pytest.mark.parametrize("obj", OBJECTS, ids=IDS)
def test_description_fields(obj):
    assert isinstance(obj, ObjectModel)
    assert obj.source == f"builtin:{obj.name}"
    assert obj.color_name in COLORS and tuple(obj.rgba) == COLORS[obj.color_name]
    assert len(obj.rgba) == 4 and all(0.0 <= c <= 1.0 for c in obj.rgba)
    assert isinstance(obj.visual, trimesh.Trimesh) and len(obj.visual.faces) > 0


@pytest.mark.parametrize("obj", OBJECTS, ids=IDS)
def test_every_part_is_convex_watertight_with_outward_normals(obj):
    assert 1 <= len(obj.parts) <= 24
    for i, part in enumerate(obj.parts):
        assert isinstance(part, trimesh.Trimesh)
        assert part.is_convex, f"{obj.name} part {i}"
        assert part.is_watertight and part.is_winding_consistent, f"{obj.name} part {i}"
        assert part.volume > 1e-8, f"{obj.name} part {i}: signed volume {part.volume}"
        assert len(part.vertices) <= 200, f"{obj.name} part {i}: {len(part.vertices)} vertices"


@pytest.mark.parametrize("obj", OBJECTS, ids=IDS)
def test_stands_on_the_table_centred(obj):
    lo, hi = obj.bounds_m()
    assert abs(lo[2]) <= 1e-9
    assert np.allclose((lo[:2] + hi[:2]) / 2.0, 0.0, atol=1e-9)
    assert abs(obj.visual.bounds[0][2]) <= 1e-9


@pytest.mark.parametrize("obj", OBJECTS, ids=IDS)
def test_parts_are_connected(obj):
    """No part floats free: the graph of parts whose bounding boxes touch is connected."""
    boxes = [p.bounds for p in obj.parts]
    reached, todo = {0}, [0]
    while todo:
        a = todo.pop()
        for b in range(len(boxes)):
            if b not in reached and np.all(boxes[a][0] <= boxes[b][1] + 1e-9) \
                    and np.all(boxes[b][0] <= boxes[a][1] + 1e-9):
                reached.add(b)
                todo.append(b)
    assert reached == set(range(len(boxes)))


@pytest.mark.parametrize("obj", OBJECTS, ids=IDS)
def test_household_size(obj):
    ext = obj.extents_m()
    assert 0.03 <= ext.max() <= 0.16, ext
    assert ext.min() >= 0.015, ext
    assert 5e-6 <= obj.volume_m3() <= 1e-3  # 5 cm^3 .. 1 l


@pytest.mark.parametrize("obj", OBJECTS, ids=IDS)
def test_graspable_across_one_side_by_the_8cm_gripper(obj):
    width, _ = footprint_min_width_m(obj)
    assert MIN_GRASP_WIDTH_M <= width <= MAX_GRASP_WIDTH_M, f"{obj.name}: {width * 1000:.1f} mm"


def test_footprint_width_matches_a_brute_force_yaw_sweep():
    for obj in OBJECTS:
        xy = np.vstack([p.vertices[:, :2] for p in obj.parts])
        yaws = np.linspace(0.0, np.pi, 3601)
        dirs = np.column_stack([np.cos(yaws), np.sin(yaws)])
        proj = xy @ dirs.T
        brute = (proj.max(axis=0) - proj.min(axis=0)).min()
        width, yaw = footprint_min_width_m(obj)
        assert width <= brute + 1e-9 and brute - width < 2e-4, obj.name
        d = np.array([np.cos(yaw), np.sin(yaw)])
        assert np.ptp(xy @ d) == pytest.approx(width, abs=1e-9)


def test_mugs_are_grasped_across_the_body_not_the_handle():
    for obj in (o for o in OBJECTS if o.category == "mug"):
        width, _ = footprint_min_width_m(obj)
        across_y = obj.extents_m()[1]  # the handle sticks out along +x; close along y
        assert across_y <= MAX_GRASP_WIDTH_M and across_y - width < 1e-3  # a polygon: vertex vs edge width
        assert obj.extents_m()[0] > across_y + 0.015  # the handle does stick out


def test_hollow_objects_are_open_at_the_top():
    """A mug or bowl is a ring around an empty middle, not a solid."""
    for obj in (o for o in OBJECTS if o.category in ("mug", "bowl")):
        top = obj.extents_m()[2]
        probe = np.array([[0.0, 0.0, top * 0.8]])
        assert not any(p.contains(probe)[0] for p in obj.parts), obj.name


def test_deterministic_within_and_across_processes():
    def digest(objs):
        return [float(np.sum(p.vertices * np.arange(1, 4))) for o in objs for p in o.parts]

    again = builtin_objects()
    for a, b in zip(OBJECTS, again):
        assert len(a.parts) == len(b.parts)
        for pa, pb in zip(a.parts, b.parts):
            assert np.array_equal(pa.vertices, pb.vertices) and np.array_equal(pa.faces, pb.faces)
    code = ("import numpy as np; from grasp_pipeline.objects.builtin import builtin_objects as b;"
            "print(repr([float(np.sum(p.vertices * np.arange(1, 4))) for o in b() for p in o.parts]))")
    python_dir = Path(__file__).resolve().parents[3] / "python"
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                         env={"PYTHONPATH": str(python_dir), "PYTHONHASHSEED": "12345"})
    assert res.returncode == 0, res.stderr[-2000:]
    assert eval(res.stdout) == digest(OBJECTS)


def test_builtin_object_returns_a_fresh_copy():
    a = builtin_object("red_mug")
    a.parts[0].apply_translation((1.0, 0.0, 0.0))
    b = builtin_object("red_mug")
    assert abs(b.parts[0].bounds[0][0] - a.parts[0].bounds[0][0]) == pytest.approx(1.0)
    assert np.allclose(b.bounds_m()[:, :2].sum(axis=0), 0.0, atol=1e-9)


def test_unknown_name_lists_the_known_names():
    with pytest.raises(MeshError) as err:
        builtin_object("purple_elephant")
    msg = str(err.value)
    assert "purple_elephant" in msg and "red_mug" in msg and "tall_bottle" in msg
