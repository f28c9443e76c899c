"""Colour names from RGB: exact references, shading, uint8 input, an object's robust colour."""

import numpy as np
import pytest

from grasp_pipeline.language import LanguageConfig, colour_name, object_colour
from grasp_pipeline.objects.builtin import COLORS

CHROMATIC = [n for n in COLORS if n not in ("white", "grey", "silver")]


@pytest.mark.parametrize("name", sorted(COLORS))
def test_every_builtin_colour_gets_its_own_name(name):
    # the dataset recorder names ground-truth colours with this function
    assert colour_name(COLORS[name]) == name          # RGBA: the alpha is ignored
    assert colour_name(COLORS[name][:3]) == name


@pytest.mark.parametrize("name", CHROMATIC)
@pytest.mark.parametrize("shade", [0.8, 0.5, 0.3])
def test_shading_keeps_a_chromatic_name(name, shade):
    rgb = np.array(COLORS[name][:3]) * shade
    assert colour_name(rgb) == name


def test_uint8_and_0_255_numbers_are_read_as_bytes():
    assert colour_name(np.array([217, 38, 33], dtype=np.uint8)) == "red"
    assert colour_name((38, 89, 217)) == "blue"


def test_black_and_a_dark_grey():
    assert colour_name((0.02, 0.02, 0.02)) == "black"
    assert colour_name((0.5, 0.5, 0.5)) == "grey"


def test_object_colour_ignores_highlights_and_dark_edges():
    rng = np.random.default_rng(0)
    body = np.array([0.95, 0.55, 0.10]) * rng.uniform(0.4, 0.9, size=(200, 1))  # shaded orange
    highlights = np.tile([1.0, 1.0, 0.9], (300, 1))                             # clipped
    edges = np.tile([0.05, 0.05, 0.05], (100, 1))                                # table shadow
    samples = (np.vstack([body, highlights, edges]) * 255).astype(np.uint8)
    rgb = object_colour(samples)
    assert colour_name(rgb) == "orange"
    assert colour_name(np.median(samples, axis=0)) != "orange"  # a plain median would not do


def test_object_colour_of_nothing_is_nan():
    assert np.isnan(object_colour(np.zeros((0, 3), np.uint8))).all()


def test_a_custom_vocabulary_is_used():
    cfg = LanguageConfig(colour_names=("crimson", "teal"), colour_rgb=((0.8, 0.1, 0.1), (0.0, 0.5, 0.5)),
                         colour_synonyms=())
    assert colour_name((0.9, 0.2, 0.2), cfg) == "crimson"
