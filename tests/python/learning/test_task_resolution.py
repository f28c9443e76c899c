"""The reference policy's ladder from a task's description to one perceived object."""

import pytest

from grasp_pipeline.language.attributes import PerceivedObject
from grasp_pipeline.language.config import LanguageConfig
from grasp_pipeline.language.exceptions import AmbiguousDescriptionError, NoMatchError
from grasp_pipeline.language.resolver import resolve
from grasp_pipeline.learning.task_resolution import resolution_ladder

CFG = LanguageConfig()


def _obj(tid: int, colour: str, shape: str) -> PerceivedObject:
    return PerceivedObject(tid=tid, colour=colour, shape=shape, center_m=(0.4 + 0.05 * tid, 0.0, 0.23),
                           extents_m=(0.05, 0.05, 0.05), distance_m=0.4 + 0.05 * tid)


def _first_single(description: str, objects) -> int:
    """The track id the first query of the ladder naming exactly one object resolves to."""
    for d, among in resolution_ladder(description, objects, CFG):
        try:
            return resolve(d, among, CFG).tid
        except (NoMatchError, AmbiguousDescriptionError):
            continue
    raise LookupError(description)


def test_the_exact_description_wins_when_it_names_one_object():
    objects = [_obj(0, "red", "box"), _obj(1, "red", "cylinder"), _obj(2, "blue", "box")]
    assert _first_single("the red box", objects) == 0


def test_a_shape_perception_does_not_name_falls_back_to_the_colour_among_unnamed_shapes():
    # an L block ("the red block"): perceived as no known shape, beside a red cylinder
    objects = [_obj(0, "yellow", "other"), _obj(2, "red", "cylinder"), _obj(3, "red", "other")]
    assert _first_single("the red block", objects) == 3
    # a prism ("the yellow object"): the yellow cylinder is another shape
    objects = [_obj(0, "yellow", "cylinder"), _obj(2, "yellow", "other"), _obj(3, "purple", "box")]
    assert _first_single("the yellow object", objects) == 2


def test_an_achromatic_colour_seen_as_another_achromatic_one_is_found():
    # a grey stone seen as white, beside a silver cylinder
    objects = [_obj(0, "silver", "cylinder"), _obj(1, "white", "other"), _obj(2, "purple", "box")]
    assert _first_single("the grey object", objects) == 1
    # a white mug seen grey
    assert _first_single("the white mug", [_obj(0, "orange", "box"), _obj(1, "grey", "mug")]) == 1


def test_two_objects_of_the_colour_and_no_shape_to_tell_them_apart_stay_unresolved():
    objects = [_obj(0, "red", "other"), _obj(1, "red", "other")]
    with pytest.raises(LookupError):
        _first_single("the red object", objects)
    # a chromatic colour is never swapped for another one
    with pytest.raises(LookupError):
        _first_single("the orange object", [_obj(0, "red", "other"), _obj(1, "yellow", "box")])
