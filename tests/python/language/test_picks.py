"""resolve_picks: descriptions in order → targets and report records; one object named twice."""

import pytest

from grasp_pipeline.language import NoMatchError, PerceivedObject, SameObjectError, resolve_picks
from grasp_pipeline.report.serialize import to_jsonable

OBJS = [PerceivedObject(1, "red", "mug", (0.5, 0.1, 0.25), (0.07, 0.09, 0.09), 0.51),
        PerceivedObject(2, "blue", "box", (0.45, -0.1, 0.22), (0.04, 0.04, 0.04), 0.46),
        PerceivedObject(3, "green", "box", (0.6, 0.0, 0.23), (0.05, 0.05, 0.06), 0.6)]


def test_targets_in_the_order_given_and_records():
    out = []
    targets = resolve_picks(["the tallest box", "the red mug"], OBJS, out)
    assert targets == [(0.6, 0.0), (0.5, 0.1)]
    rec = to_jsonable(out[1])
    assert rec["description"] == "the red mug" and rec["tid"] == 1 and rec["described"] == "the red mug"
    assert rec["size"] == "large" and rec["shape"] == "mug" and rec["center"] == [0.5, 0.1, 0.25]


def test_one_object_named_twice_is_refused():
    with pytest.raises(SameObjectError, match=r"'the red mug' and 'the tallest object' both name #1"):
        resolve_picks(["the red mug", "the tallest object"], OBJS, [])


def test_resolutions_before_a_refusal_are_kept():
    out = []
    with pytest.raises(NoMatchError):
        resolve_picks(["the blue box", "the yellow can"], OBJS, out)
    assert [r.tid for r in out] == [2]
