"""Task text from a target's attributes."""

from types import SimpleNamespace

from grasp_pipeline.dataset.tasks import object_phrase, task_text
from grasp_pipeline.objects.builtin import builtin_object
from grasp_pipeline.sim.scene_spec import ObjectSpec

TEMPLATE = "pick up the {object} and put it in the tray"


def _spec(**kw):
    return ObjectSpec(name=kw.pop("name", "o"), kind=kw.pop("kind", "cube"), size_m=(0.04, 0.04, 0.04),
                      position_m=(0.5, 0.0, 0.22), **kw)


def test_colour_name_and_category_of_a_mesh_object():
    mug = builtin_object("red_mug")
    obj = _spec(kind="mesh", mesh=mug, category=mug.category)
    assert object_phrase(obj) == f"{mug.color_name} {mug.category}" == "red mug"
    assert task_text(TEMPLATE, obj) == "pick up the red mug and put it in the tray"


def test_without_a_colour_name_the_rgba_is_named_with_the_resolvers_words():
    assert object_phrase(_spec(kind="cylinder", rgba=(0.85, 0.15, 0.15, 1.0))) == "red cylinder"
    assert object_phrase(_spec(kind="cuboid", category="box", rgba=(0.15, 0.25, 0.85, 1.0))) == "blue box"


def test_without_any_colour_the_colour_is_omitted():
    assert object_phrase(SimpleNamespace(kind="cylinder", category="")) == "cylinder"
