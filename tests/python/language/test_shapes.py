"""Shape words from synthetic point clouds of what a camera above sees of an object."""

import numpy as np
import pytest

from grasp_pipeline.language.shapes import classify, shape_features, shape_word

RNG = np.random.default_rng(1)
STEP_M = 0.002


def _grid(x0, x1, y0, y1):
    x, y = np.meshgrid(np.arange(x0, x1 + 1e-9, STEP_M), np.arange(y0, y1 + 1e-9, STEP_M))
    return x.ravel(), y.ravel()


def _disc(r, z, r_in=0.0, cx=0.0):
    x, y = _grid(-r, r, -r, r)
    rr = np.hypot(x, y)
    keep = (rr <= r) & (rr >= r_in)
    return np.column_stack([x[keep] + cx, y[keep], np.full(keep.sum(), z)])


def _rect(w, p, z):
    x, y = _grid(-w / 2, w / 2, -p / 2, p / 2)
    return np.column_stack([x, y, np.full(len(x), z)])


def _side(r, z0, z1, cx=0.0):
    a, z = np.meshgrid(np.linspace(0, 2 * np.pi, 120), np.arange(z0, z1, STEP_M))
    return np.column_stack([cx + r * np.cos(a).ravel(), r * np.sin(a).ravel(), z.ravel()])


def _noisy(p):
    return p + RNG.normal(0, 0.0007, p.shape)


def _word(points, extents):
    """The object's box centred at the origin, axes = world axes; z from 0 (table) up."""
    h = extents[2]
    return shape_word(_noisy(points) - [0, 0, h / 2], np.zeros(3), np.eye(3), extents)


def test_a_cuboid_is_a_box():
    assert _word(np.vstack([_rect(0.06, 0.04, 0.05), _rect(0.06, 0.04, 0.03)[::3] * [1, 1, 0.5]]),
                 (0.06, 0.04, 0.05)) == "box"


def test_a_can_is_a_cylinder():
    pts = np.vstack([_disc(0.03, 0.12), _side(0.03, 0.01, 0.12)[::4]])
    assert _word(pts, (0.06, 0.06, 0.12)) == "cylinder"


def test_a_mug_is_hollow_and_stands_tall():
    rim = _disc(0.034, 0.09, r_in=0.03)
    inside = _disc(0.03, 0.012)                                  # its bottom, seen from above
    handle = _rect(0.008, 0.02, 0.08) + [0.045, 0, 0]
    pts = np.vstack([rim, inside, handle, _side(0.034, 0.01, 0.09)[::4]]) - [0.006, 0, 0]
    assert _word(pts, (0.088, 0.068, 0.09)) == "mug"


def test_a_bowl_is_hollow_but_low_so_other():
    pts = np.vstack([_disc(0.035, 0.032, r_in=0.03), _disc(0.028, 0.012)])
    assert _word(pts, (0.07, 0.07, 0.032)) == "other"


def test_a_bottle_narrows_to_its_neck():
    body_top = _disc(0.032, 0.11, r_in=0.013)          # the shoulder, seen from above
    neck = _disc(0.013, 0.155)
    pts = np.vstack([body_top, neck, _side(0.013, 0.11, 0.155), _side(0.032, 0.01, 0.11)[::4]])
    assert _word(pts, (0.064, 0.064, 0.155)) == "bottle"


def test_a_t_block_is_other():
    bar = _rect(0.07, 0.02, 0.025) + [0, 0.025, 0]
    stem = _rect(0.02, 0.05, 0.025) + [0, -0.01, 0]
    assert _word(np.vstack([bar, stem]), (0.07, 0.07, 0.025)) == "other"


def test_a_neighbours_points_outside_the_box_are_left_out():
    can = np.vstack([_disc(0.03, 0.12), _side(0.03, 0.01, 0.12)[::4]])
    neighbour = _rect(0.05, 0.05, 0.04) + [0.07, 0, 0]   # merged into this track in some frame
    assert _word(np.vstack([can, neighbour]), (0.06, 0.06, 0.12)) == "cylinder"


def test_too_few_points_is_other():
    f = shape_features(np.zeros((2, 3)), np.zeros(3), np.eye(3), (0.05, 0.05, 0.05))
    assert np.isnan(f.fill) and classify(f) == "other"
