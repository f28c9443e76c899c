"""Free space for the fingers (the declutter order): footprint geometry and the ranking."""

from types import SimpleNamespace

import numpy as np
import pytest

from grasp_pipeline.orchestration.grasping.accessibility import (accessibility_m, box_footprint,
                                                                 polygon_distance_m,
                                                                 rank_by_accessibility)
from grasp_pipeline.robot.description import HandClearances

HAND = HandClearances(0.011, 0.0394, finger_thickness_m=0.02, finger_width_m=0.02)
MARGIN = 0.02


def _track(x, y, w=0.05, pw=0.05, yaw=0.0):
    c, s = np.cos(yaw), np.sin(yaw)
    R = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])
    return SimpleNamespace(smoothed=SimpleNamespace(center=[x, y, 0.225], R_box=R, extents=[w, pw, 0.05]))


def test_polygon_distance():
    a = box_footprint([0, 0, 0], np.eye(3), [0.1, 0.1, 0.1])
    assert polygon_distance_m(a, box_footprint([0.15, 0, 0], np.eye(3), [0.1, 0.1, 0.1])) == pytest.approx(0.05)
    assert polygon_distance_m(a, box_footprint([0.05, 0.05, 0], np.eye(3), [0.1, 0.1, 0.1])) == 0.0
    rot = np.array([[np.cos(0.785398), -np.sin(0.785398), 0], [np.sin(0.785398), np.cos(0.785398), 0], [0, 0, 1]])
    d = polygon_distance_m(a, box_footprint([0.2, 0, 0], rot, [0.1, 0.1, 0.1]))
    assert d == pytest.approx(0.2 - 0.05 - 0.05 * np.sqrt(2), abs=1e-6)


def test_fingers_measure_the_gap_along_the_closing_axis():
    target = _track(0.5, 0.0, w=0.04, pw=0.09)        # closes along x; y side too wide
    beside = _track(0.5, 0.10, w=0.05, pw=0.05)       # across the closing axis, 5.5 cm away
    ahead = _track(0.5 + 0.02 + 0.07, 0.0)            # on the closing axis
    free = accessibility_m(target, [beside], HAND, MARGIN, 0.06)
    blocked = accessibility_m(target, [ahead], HAND, MARGIN, 0.06)
    # finger outer face at 0.02 + 0.01 + 0.02 = 0.05 from the centre; the box ahead starts at 0.065
    assert blocked == pytest.approx(0.015, abs=1e-6)
    assert free > blocked
    assert accessibility_m(target, [], HAND, MARGIN, 0.06) == float("inf")


def test_the_perpendicular_grasp_counts_when_it_fits():
    target = _track(0.5, 0.0, w=0.04, pw=0.05)
    ahead = _track(0.5 + 0.055, 0.0)                  # blocks the preferred axis entirely
    assert accessibility_m(target, [ahead], HAND, MARGIN, 0.06) > 0.0
    assert accessibility_m(target, [ahead], HAND, MARGIN, 0.045) == 0.0


def test_ranking_puts_free_objects_first_and_keeps_nearest_first_among_free_ones():
    crowded = [_track(0.45, 0.0), _track(0.45 + 0.06, 0.0)]   # 1 cm apart along x
    loose = _track(0.60, 0.15)
    tracks = crowded + [loose]
    targets = [(0.45, 0.0), (0.51, 0.0), (0.60, 0.15)]
    assert rank_by_accessibility(targets, tracks, HAND, MARGIN, 0.06, enough_m=0.03)[0] == (0.60, 0.15)
    far = [_track(0.4, 0.0), _track(0.6, 0.2)]
    assert rank_by_accessibility([(0.4, 0.0), (0.6, 0.2)], far, HAND, MARGIN, 0.06, 0.03) == [(0.4, 0.0), (0.6, 0.2)]
