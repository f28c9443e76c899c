"""The geometric bound of a grasp on shapes whose answers follow by hand (75 mm limit, 60° tilt,
pads at least 10 mm above the table)."""

import math

import numpy as np
import pytest
import trimesh

from grasp_pipeline.evaluation.config import GraspBoundConfig
from grasp_pipeline.evaluation.grasp_bound import ConvexShape, bounds_of_spec, grasp_bound
from grasp_pipeline.exceptions import ConfigError
from grasp_pipeline.objects.model import ObjectModel
from grasp_pipeline.sim.scene_spec import ObjectSpec, SceneSpec

CFG = GraspBoundConfig()


def _rot_y(deg):
    a = math.radians(deg)
    return np.array([[math.cos(a), 0, math.sin(a)], [0, 1, 0], [-math.sin(a), 0, math.cos(a)]])


def _on_table(points, R=np.eye(3)):
    """``points`` rotated by ``R`` and lifted so that the lowest rests on the table (z = 0)."""
    p = np.asarray(points, float) @ np.asarray(R).T
    return p - [0.0, 0.0, p[:, 2].min()]


def _box(x, y, z, R=np.eye(3)):
    return _on_table(trimesh.creation.box(extents=(x, y, z)).vertices, R)


def _bound(points, config=CFG):
    return grasp_bound(ConvexShape.of_points(points), 0.0, config)


def _mm(v):
    return None if v is None else 1e3 * v


@pytest.mark.parametrize("name, points, label, width_only", [
    ("50 mm cube", _box(0.05, 0.05, 0.05), "top_down", "top_down"),
    # 100 mm wide from above; at 60° the narrowest closing spans 100 cos 60° + 30 sin 60° = 76 mm;
    # only a steep closing fits (30 mm vertically), with one pad under the slab
    ("100x100x30 slab lying flat", _box(0.10, 0.10, 0.03), "none", "any_side"),
    ("100x60x150 box standing on its 100x60 end", _box(0.10, 0.06, 0.15), "top_down", "top_down"),
    ("the same box lying flat (150x100 down)", _box(0.15, 0.10, 0.06), "none", "any_side"),
    ("the same box on its side (150x60 down)", _box(0.15, 0.06, 0.10), "top_down", "top_down"),
    # 120 cos 60° + 10 sin 60° = 68.7 mm at 60°: only a pad under the plate would close on it
    ("120x120x10 plate lying flat", _box(0.12, 0.12, 0.01), "none", "tilted"),
    ("sphere of 90 mm", _on_table(trimesh.creation.icosphere(3, 0.045).vertices), "none", "none"),
])
def test_labels_of_shapes_with_known_answers(name, points, label, width_only):
    b = _bound(points)
    assert (b.label, b.label_width_only) == (label, width_only), (name, b)


def test_a_long_cylinder_lying_down_is_grasped_across_from_above():
    cyl = trimesh.creation.cylinder(radius=0.02, height=0.20, sections=64).vertices
    b = _bound(_on_table(cyl, _rot_y(90)))
    assert b.label == "top_down"
    assert _mm(b.narrowest_m["top_down"]) == pytest.approx(40.0, abs=0.05)  # across, at mid-height


def test_the_narrowest_widths_of_boxes_are_exact():
    b = _bound(_box(0.10, 0.10, 0.03))
    assert _mm(b.narrowest_width_only_m["top_down"]) == pytest.approx(100.0, abs=1e-6)
    assert _mm(b.narrowest_width_only_m["tilted"]) == pytest.approx(100 * 0.5 + 30 * math.sqrt(3) / 2, abs=1e-6)
    assert _mm(b.narrowest_width_only_m["any_side"]) == pytest.approx(30.0, abs=1e-6)
    assert _mm(_bound(_box(0.05, 0.05, 0.05)).narrowest_m["top_down"]) == pytest.approx(50.0, abs=1e-6)


def test_a_box_leaning_on_its_long_edge_is_grasped_tilted_not_from_above():
    # 120 x 90 x 50 mm resting on a 120 mm edge, its 120 x 90 face 35° from the table: from above
    # it is 90 cos 35° + 50 sin 35° = 102.4 mm wide; across its 50 mm it closes 55° above the
    # table, within the 60° tilt, and both pads touch it above the table
    b = _bound(_box(0.09, 0.12, 0.05, _rot_y(35)))
    assert (b.label, b.label_width_only) == ("tilted", "tilted")
    assert _mm(b.narrowest_m["top_down"]) == pytest.approx(90 * math.cos(math.radians(35))
                                                           + 50 * math.sin(math.radians(35)), abs=1e-3)
    assert _mm(b.narrowest_m["tilted"]) == pytest.approx(50.0, abs=1e-3)


def test_the_tilt_limit_is_a_limit():
    # leaning only 10°, across its 50 mm it closes 80° above the table; the closest direction
    # within 60° spans 50 cos 20° + 90 sin 20° = 77.8 mm: any side, not tilted
    b = _bound(_box(0.09, 0.12, 0.05, _rot_y(10)))
    assert b.label == "any_side"
    assert _mm(b.narrowest_width_only_m["tilted"]) == pytest.approx(
        50 * math.cos(math.radians(20)) + 90 * math.sin(math.radians(20)), abs=0.3)
    assert _bound(_box(0.09, 0.12, 0.05, _rot_y(10)), GraspBoundConfig(tilted_limit_deg=80.0)).label == "tilted"


def test_the_width_limit_and_the_table_rule_are_parameters():
    slab = _box(0.10, 0.10, 0.03)
    assert _bound(slab, GraspBoundConfig(max_width_m=0.077)).label_width_only == "tilted"  # 76 mm at 60°
    assert _bound(slab, GraspBoundConfig(min_contact_height_m=0.0)).label == "any_side"  # rule off
    flat = _box(0.04, 0.04, 0.008)  # 8 mm high: the pads cannot touch it 10 mm above the table
    assert (_bound(flat).label, _bound(flat).label_width_only) == ("none", "top_down")
    with pytest.raises(ConfigError, match="tilted_limit_deg"):
        GraspBoundConfig(tilted_limit_deg=90.0).validate()


def _spec(obj):
    return SceneSpec("s", (obj,), 0.4, (0.0,) * 7)


def test_scene_objects_are_labelled_where_the_scene_placed_them():
    c35, s35 = math.cos(math.radians(17.5)), math.sin(math.radians(17.5))
    leaning = (c35, 0.0, s35, 0.0)  # 35° about y, its lowest edge on the table (z = 0.4)
    z = 0.4 + 0.045 * math.sin(math.radians(35)) + 0.025 * math.cos(math.radians(35))
    box = ObjectSpec("box", "cuboid", (0.09, 0.12, 0.05), (0.5, 0.0, z), quat_wxyz=leaning)
    assert bounds_of_spec(_spec(box), CFG)["box"].label == "tilted"
    upright = ObjectSpec("box", "cuboid", (0.09, 0.12, 0.05), (0.5, 0.0, 0.425))
    assert bounds_of_spec(_spec(upright), CFG)["box"].label == "none"  # lying on its 120 x 90 face
    can = ObjectSpec("can", "cylinder", (0.066, 0.066, 0.12), (0.5, 0.0, 0.46))
    assert bounds_of_spec(_spec(can), CFG)["can"].label == "top_down"
    # a mesh object: its collision parts, about the centre of their bounding box
    part = trimesh.creation.box(extents=(0.09, 0.12, 0.05))
    part.apply_translation([0.0, 0.0, 0.025])  # model frame: the bottom face's centre at 0
    mesh = ObjectSpec("m", "mesh", (0.09, 0.12, 0.05), (0.5, 0.0, z), mesh=ObjectModel("m", (part,)),
                      quat_wxyz=leaning)
    b = bounds_of_spec(_spec(mesh), CFG)["m"]
    assert b.label == "tilted" and _mm(b.narrowest_m["tilted"]) == pytest.approx(50.0, abs=1e-3)
