"""A perceived object's attributes; relative sizes; tracks of one object seen in parts."""

from types import SimpleNamespace as NS

import numpy as np

from grasp_pipeline.language import PerceivedObject, perceive_objects, perceived_object, relative_sizes
from grasp_pipeline.language.attributes import UNKNOWN_COLOUR, stacked_groups


def _track(tid, center, extents, yaw=0.0):
    c, s = np.cos(yaw), np.sin(yaw)
    R = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])
    return NS(tid=tid, smoothed=NS(center=np.array(center, float), R_box=R, extents=np.array(extents, float)))


def _cylinder_points(center, r, h):
    a, z = np.meshgrid(np.linspace(0, 2 * np.pi, 90), np.linspace(0, h, 30))
    side = np.column_stack([r * np.cos(a).ravel(), r * np.sin(a).ravel(), z.ravel()])
    x, y = np.meshgrid(np.linspace(-r, r, 40), np.linspace(-r, r, 40))
    keep = np.hypot(x, y) <= r
    top = np.column_stack([x[keep], y[keep], np.full(keep.sum(), h)])
    return np.vstack([side[::3], top]) + [center[0], center[1], center[2] - h / 2]


def test_perceived_object_from_box_points_and_colours():
    pts = _cylinder_points((0.5, 0.1, 0.26), 0.03, 0.12)
    colours = np.tile(np.array([200, 40, 35], np.uint8), (50, 1))
    o = perceived_object(7, (0.5, 0.1, 0.26), np.eye(3), (0.06, 0.06, 0.12), pts, colours)
    assert (o.tid, o.colour, o.shape) == (7, "red", "cylinder")
    assert np.isclose(o.distance_m, np.hypot(0.5, 0.1))      # from the robot base (origin)
    assert np.isclose(o.height_m, 0.12) and np.isclose(o.volume_m3, 0.06 * 0.06 * 0.12)


def test_without_observations_colour_is_unknown_and_shape_other():
    o = perceived_object(1, (0.5, 0, 0.2), np.eye(3), (0.05, 0.05, 0.05), None, None)
    assert (o.colour, o.shape) == (UNKNOWN_COLOUR, "other")


def test_relative_sizes_against_the_median_volume():
    objs = [PerceivedObject(i, "red", "box", (0, 0, 0), (s, s, s), 0.0)
            for i, s in enumerate([0.02, 0.04, 0.045, 0.05, 0.08])]
    assert relative_sizes(objs) == {0: "small", 1: "", 2: "", 3: "", 4: "large"}
    assert relative_sizes([]) == {}


def test_a_bottles_neck_track_joins_its_body_track():
    body = _track(8, (0.45, 0.02, 0.26), (0.063, 0.063, 0.112))
    neck = _track(2, (0.45, 0.021, 0.28), (0.028, 0.028, 0.155), yaw=0.3)
    other = _track(4, (0.60, 0.09, 0.22), (0.03, 0.03, 0.03))
    groups = stacked_groups([neck, other, body], margin_m=0.004)
    assert [[t.tid for t in g] for g in groups] == [[8, 2], [4]]


def test_merged_object_has_the_tallest_height_and_every_members_points():
    body = _track(8, (0.45, 0.0, 0.256), (0.064, 0.064, 0.112))
    neck = _track(2, (0.45, 0.0, 0.2775), (0.028, 0.028, 0.155))
    body_pts = _cylinder_points((0.45, 0.0, 0.256), 0.032, 0.112)
    neck_pts = _cylinder_points((0.45, 0.0, 0.2775), 0.013, 0.155)
    neck_pts = neck_pts[neck_pts[:, 2] > 0.2 + 0.112]
    obs = NS(tracks={8: NS(points=body_pts, colour_samples=lambda: np.tile([40, 180, 190], (10, 1)).astype(np.uint8)),
                     2: NS(points=neck_pts, colour_samples=lambda: np.zeros((0, 3), np.uint8))})
    [o] = perceive_objects([neck, body], obs)
    assert o.tid == 8 and np.isclose(o.height_m, 0.155) and o.colour == "cyan"
    assert o.shape == "bottle"
