"""Descriptions → wanted attributes; unknown words and unreadable descriptions refused."""

import pytest

from grasp_pipeline.exceptions import GraspPipelineError, InputError
from grasp_pipeline.language import DescriptionError, UnknownWordError, Wanted, parse


@pytest.mark.parametrize("text, wanted", [
    ("the red mug", Wanted(colour="red", shape="mug")),
    ("The tallest box", Wanted(shape="box", superlative="tallest")),
    ("a small blue can", Wanted(colour="blue", shape="cylinder", size="small")),
    ("the nearest object", Wanted(superlative="nearest")),
    ("the large green bottle.", Wanted(colour="green", shape="bottle", size="large")),
    ("the big gray cup", Wanted(colour="grey", shape="mug", size="large")),
    ("closest red one", Wanted(colour="red", superlative="nearest")),
    ("cube", Wanted(shape="box")),
])
def test_words_and_synonyms(text, wanted):
    assert parse(text) == wanted


def test_unknown_words_are_refused_with_the_vocabulary():
    with pytest.raises(UnknownWordError) as err:
        parse("the shiny red mug on the left")
    msg = str(err.value)
    assert "unknown word(s) 'shiny', 'on', 'left'" in msg
    assert "colour: black, blue," in msg and "shape: block, bottle, box, can," in msg
    assert "size: big, biggest, closest" in msg
    assert isinstance(err.value, InputError) and isinstance(err.value, GraspPipelineError)


@pytest.mark.parametrize("text, match", [
    ("the red blue mug", "names more than one colour"),
    ("the mug bottle", "names more than one shape"),
    ("", "names no object"),
    ("the", "names no object"),
])
def test_descriptions_that_cannot_be_read(text, match):
    with pytest.raises(DescriptionError, match=match):
        parse(text)


def test_phrase_is_the_normalised_description():
    assert parse("a big can").phrase() == "large cylinder"
    assert parse("the nearest one").phrase() == "nearest object"
