"""resolve() on synthetic perceived objects: matches, superlatives, ties and the refusals."""

import pytest

from grasp_pipeline.language import (AmbiguousDescriptionError, NoMatchError, PerceivedObject,
                                     describe, resolve)


def obj(tid, colour, shape, extents, xy=(0.5, 0.0)):
    return PerceivedObject(tid, colour, shape, (xy[0], xy[1], 0.25), extents,
                           distance_m=float((xy[0] ** 2 + xy[1] ** 2) ** 0.5))


TABLE = [
    obj(1, "red", "box", (0.06, 0.06, 0.06), (0.60, -0.10)),
    obj(2, "blue", "cylinder", (0.03, 0.03, 0.06), (0.45, 0.10)),
    obj(3, "red", "mug", (0.07, 0.09, 0.09), (0.50, 0.00)),
    obj(4, "green", "bottle", (0.06, 0.06, 0.15), (0.55, 0.15)),
    obj(5, "blue", "box", (0.02, 0.02, 0.02), (0.42, -0.05)),
]


@pytest.mark.parametrize("text, tid", [
    ("the red mug", 3), ("the red box", 1), ("the tallest object", 4), ("the tallest box", 1),
    ("the nearest object", 5), ("the nearest blue object", 5), ("a small blue box", 5),
    ("the large green bottle", 4), ("the blue can", 2), ("the largest red object", 3),
    ("the smallest object", 5), ("the bottle", 4),
])
def test_descriptions_that_name_one_object(text, tid):
    assert resolve(text, TABLE).tid == tid


SEEN = ("seen: #1 red box, #2 blue cylinder (small), #3 red mug (large), "
        "#4 green bottle (large), #5 blue box (small)")


def test_no_match_lists_what_was_seen():
    with pytest.raises(NoMatchError) as err:
        resolve("the purple mug", TABLE)
    assert str(err.value) == f"'the purple mug': no purple mug seen; {SEEN}"


def test_a_size_word_that_fits_nothing_is_no_match():
    with pytest.raises(NoMatchError, match="no large blue cylinder seen"):
        resolve("the large blue can", TABLE)


def test_ambiguity_lists_the_candidates_and_what_was_seen():
    with pytest.raises(AmbiguousDescriptionError) as err:
        resolve("the red object", TABLE)
    assert str(err.value) == ("'the red object' fits 2 objects (#1, #3); add a colour, shape or "
                              f"size word; {SEEN}")


def test_a_superlative_tie_is_ambiguous():
    twins = [obj(1, "red", "box", (0.05, 0.05, 0.100)), obj(2, "blue", "box", (0.05, 0.05, 0.103)),
             obj(3, "red", "box", (0.05, 0.05, 0.05))]
    with pytest.raises(AmbiguousDescriptionError, match=r"fits 2 objects \(#2, #1\); they are tied"):
        resolve("the tallest box", twins)
    assert resolve("the tallest blue box", twins).tid == 2


def test_nothing_seen():
    with pytest.raises(NoMatchError, match="seen: nothing"):
        resolve("the red mug", [])


def test_describe():
    assert describe(TABLE[2]) == "the red mug"
    assert describe(obj(9, "unknown", "other", (0.03, 0.03, 0.03))) == "the object"
    assert describe(TABLE[4], "small") == "the small blue box"
