"""What happened to each object of a round (synthetic round records), the matching of tracks to
true objects, and the pooled summary with the declutter rate against each bound."""

import numpy as np
import pytest

from types import SimpleNamespace

from grasp_pipeline.evaluation.object_outcomes import (OUTCOMES, assign_outcomes, in_track_box, nearest_object,
                                                       polygon_distance_m, summarize, why_category)

NAMES = ["mug_0", "box_1", "can_2", "bottle_3", "plate_4", "pear_5"]


def _attempt(obj, ok, stage=None, reason=None):
    return {"object": obj, "success": ok, "stage": stage, "reason": reason}


def test_each_object_gets_the_first_outcome_that_applies():
    attempts = [_attempt("mug_0", False, "CLOSE", "missed"), _attempt("mug_0", True),
                _attempt("box_1", False, "GRASP", "no plan"), _attempt("box_1", False, "LIFT", "slipped"),
                _attempt(None, False, "SELECT", "nothing there")]
    skipped = [{"object": "can_2", "why": "too wide"}, {"object": "can_2", "why": "too wide"},
               {"object": "mug_0", "why": "near the tray"}, {"object": None, "why": "a glimpse"}]
    out = assign_outcomes(NAMES, attempts, skipped, last_look={"bottle_3", "box_1"}, ended_early=True,
                          errored=False, off_table={"mug_0", "plate_4"})
    assert out["mug_0"] == {"outcome": "picked", "attempts": 2}
    assert out["box_1"] == {"outcome": "attempted_failed", "stage": "LIFT", "reason": "slipped", "attempts": 2}
    assert out["plate_4"] == {"outcome": "displaced", "attempts": 0}
    assert out["can_2"] == {"outcome": "never_proposed", "why": "too wide", "attempts": 0}
    assert out["bottle_3"] == {"outcome": "round_ended", "attempts": 0}
    assert out["pear_5"] == {"outcome": "not_seen", "attempts": 0}


def test_a_round_ended_by_the_robot_finding_nothing_leaves_unseen_objects_unseen():
    out = assign_outcomes(["a", "b"], [], [{"object": "a", "why": "x"}], last_look={"b"}, ended_early=False,
                          errored=False, off_table=set())
    assert [out[n]["outcome"] for n in "ab"] == ["never_proposed", "not_seen"]
    out = assign_outcomes(["a", "b"], [_attempt("a", True)], [], last_look={"b"}, ended_early=False,
                          errored=True, off_table=set())
    assert [out[n]["outcome"] for n in "ab"] == ["picked", "round_error"]


def test_an_object_inside_the_box_of_another_objects_track_was_merged_with_it():
    out = assign_outcomes(["a", "b", "c"], [], [{"object": "a", "why": "too wide"}], last_look={"a"},
                          ended_early=False, errored=False, off_table=set(), inside_tracks={"a", "b"})
    assert [out[n]["outcome"] for n in "abc"] == ["never_proposed", "merged", "not_seen"]


def test_a_track_box_footprint_follows_its_yaw():
    c, s = np.cos(np.radians(30)), np.sin(np.radians(30))
    R = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])  # closing direction 30° from x
    track = SimpleNamespace(smoothed=SimpleNamespace(center=[0.5, 0.0, 0.1], R_box=R, extents=[0.2, 0.04, 0.1]))
    assert in_track_box((0.5 + 0.09 * c, 0.09 * s), track)          # 90 mm along its 200 mm side
    assert not in_track_box((0.5 - 0.03 * s, 0.03 * c), track)      # 30 mm across its 40 mm side


SQUARE = np.array([[0.0, 0.0], [0.1, 0.0], [0.1, 0.1], [0.0, 0.1]])  # counter-clockwise


def test_footprint_distance_and_nearest_object():
    assert polygon_distance_m(SQUARE, (0.05, 0.05)) == 0.0
    assert polygon_distance_m(SQUARE, (0.13, 0.05)) == pytest.approx(0.03)
    assert polygon_distance_m(SQUARE, (0.13, 0.14)) == pytest.approx(0.05)
    outlines = {"long": np.array([[0.0, 0.0], [0.2, 0.0], [0.2, 0.04], [0.0, 0.04]]), "cube": SQUARE + [0.25, 0.0]}
    centres = {"long": (0.1, 0.02), "cube": (0.3, 0.05)}
    # a track on the far end of the long object: nearer the cube's centre, yet on the long one
    assert nearest_object((0.19, 0.02), outlines, centres, 0.03) == "long"
    assert nearest_object((0.22, 0.08), outlines, centres, 0.03) == "cube"   # 30 mm from it
    assert nearest_object((0.22, 0.20), outlines, centres, 0.03) is None     # nothing within reach
    overlapping = {"under": SQUARE, "over": SQUARE + [0.02, 0.0]}
    assert nearest_object((0.07, 0.05), overlapping, {"under": (0.05, 0.05), "over": (0.07, 0.05)}, 0.03) == "over"


def _row(label, outcome, width_only=None, **extra):
    return {"label": label, "label_width_only": width_only or label, "outcome": outcome, **extra}


def test_summary_rates_each_bound_by_the_objects_graspable_under_it():
    rows = [_row("top_down", "picked"), _row("top_down", "picked"), _row("top_down", "never_proposed", why="#3 far"),
            _row("tilted", "picked"), _row("tilted", "attempted_failed", stage="CLOSE", reason="slipped"),
            _row("any_side", "never_proposed", why="#4 far"), _row("none", "picked", width_only="tilted"),
            _row("none", "not_seen", width_only="any_side")]
    s = summarize(rows)
    assert s["objects"] == 8 and s["picked"] == 4
    assert s["labels"] == {"top_down": 3, "tilted": 2, "any_side": 1, "none": 2}
    assert s["graspable"] == {"top_down": 3, "tilted": 5, "any_side": 6}  # nested
    assert s["graspable_fraction"]["tilted"] == round(5 / 8, 4)
    assert (s["dr_top_down"], s["dr_tilted"], s["dr_any_side"]) == (round(2 / 3, 4), 0.6, 0.5)
    assert s["graspable_width_only"] == {"top_down": 3, "tilted": 6, "any_side": 8}
    assert s["dr_width_only"] == {"top_down": round(2 / 3, 4), "tilted": round(4 / 6, 4), "any_side": 0.5}
    assert s["picked_outside_bound"] == 1
    assert s["outcomes"] == {"picked": 4, "attempted_failed": 1, "displaced": 0, "never_proposed": 2,
                             "round_ended": 0, "merged": 0, "round_error": 0, "not_seen": 1}
    assert s["label_by_outcome"]["top_down"]["never_proposed"] == 1 and s["label_by_outcome"]["none"]["picked"] == 1
    assert sum(sum(v.values()) for v in s["label_by_outcome"].values()) == 8
    assert s["never_proposed_reasons"] == {"# far": 2}
    assert s["attempted_failed_reasons"] == {"CLOSE: slipped": 1}
    assert set(s["outcomes"]) == set(OUTCOMES)


def test_summary_of_no_objects_has_no_rates():
    s = summarize([])
    assert s["objects"] == 0 and s["dr_top_down"] is None and s["graspable_fraction"]["any_side"] is None


def test_why_categories_drop_numbers_ids_and_positions():
    assert why_category("(0.512, -0.033) is over a work-cell fixture (the tray) or within 30 mm of it") == \
        "is over a work-cell fixture (the tray) or within N mm of it"
    assert why_category("#12 was first seen during the scan (probe view)") == "# was first seen during the scan (probe view)"
    assert why_category("") == "unspecified"
