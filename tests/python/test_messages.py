"""Values and messages are cut to a readable length, however big the value."""

import time

from grasp_pipeline.messages import brief, shorten


def test_brief_cuts_long_and_deeply_nested_values_at_once():
    nested = [1] * 9
    for _ in range(9):  # 9^10 leaves if walked in full
        nested = [nested] * 9
    t0 = time.perf_counter()
    text = brief(nested)
    assert time.perf_counter() - t0 < 0.1 and len(text) <= 80
    assert brief("x" * 10_000).startswith("'xxx") and len(brief("x" * 10_000)) <= 80
    assert brief(0.25) == "0.25" and brief([1, 2]) == "[1, 2]"


def test_shorten_says_how_much_was_cut():
    assert shorten("short") == "short"
    text = shorten("a" * 5000, 100)
    assert len(text) <= 100 and text.endswith("(4930 more characters)")
