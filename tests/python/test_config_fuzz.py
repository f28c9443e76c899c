"""Hypothesis fuzz of the config loader (``--config FILE`` and ``--set name=value``) over the full
range of values: every section and parameter name (and unknown ones), numbers from the smallest
subnormal to beyond float64 and 64-bit integers, NaN and infinities, text with YAML syntax in it,
nested lists and mappings, anchors and aliases, and raw text that is no YAML at all.

The invariant: the loader returns settings whose every number lies inside its declared range, or
raises a ConfigError whose message is one line of at most 1000 characters — nothing else, and
quickly. CI runs GRASP_FUZZ_EXAMPLES examples (default 30 per test, a few seconds); a long run:

    GRASP_FUZZ_EXAMPLES=20000 PYTHONPATH=python .venv/bin/python -m pytest -q \\
        tests/python/test_config_fuzz.py --hypothesis-show-statistics
"""

from __future__ import annotations

import dataclasses
import os
import string

import yaml
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from grasp_pipeline.config_ranges import check_ranges
from grasp_pipeline.exceptions import ConfigError
from grasp_pipeline.settings import SECTIONS, load_settings, section_class

EXAMPLES = int(os.environ.get("GRASP_FUZZ_EXAMPLES", "30"))
FUZZ = settings(max_examples=EXAMPLES, deadline=2000, derandomize=not os.environ.get("GRASP_FUZZ_RANDOM"),
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])

ALL = sorted(SECTIONS)
NAMES = sorted({f.name for s in ALL for f in dataclasses.fields(section_class(s))})
EDGE_NUMBERS = [0, -0.0, 1e-320, 5e-324, 1e308, -1e308, 1.7976931348623157e308, float("nan"),
                   float("inf"), -float("inf"), 2**63, 2**64, -(2**63) - 1, 10**30, 0.5, 1, -1, 3]
YAML_TEXT = st.text(alphabet=string.printable + "é中\u2028", max_size=40)

scalars = st.one_of(st.sampled_from(EDGE_NUMBERS), st.floats(allow_nan=True, allow_infinity=True),
                    st.integers(), st.booleans(), st.none(), YAML_TEXT)
values = st.recursive(scalars, lambda inner: st.one_of(st.lists(inner, max_size=6),
                                                       st.dictionaries(YAML_TEXT, inner, max_size=4)),
                      max_leaves=30)
names = st.one_of(st.sampled_from(NAMES), YAML_TEXT)
#: A set's own names with any values (the range checks' inputs) ...
own = st.sampled_from(ALL).flatmap(lambda s: st.dictionaries(
    st.just(s), st.dictionaries(st.sampled_from([f.name for f in dataclasses.fields(section_class(s))]),
                                values, min_size=1, max_size=3), min_size=1))
#: ... or anything (unknown sections and names, values that are no mapping).
sections = st.one_of(own, st.dictionaries(st.one_of(st.sampled_from(ALL), YAML_TEXT),
                                          st.one_of(st.dictionaries(names, values, max_size=6), values),
                                          max_size=4))


def _check(fn, *args) -> None:
    try:
        loaded = fn(*args)
    except ConfigError as exc:
        msg = str(exc)
        assert "\n" not in msg and 0 < len(msg) <= 1000, msg[:2000]
        event("refused: " + ("out of range" if "out of range" in msg else "unknown name" if "unknown" in msg
                             else "type" if "cannot use" in msg or " is not " in msg else "other"))
        return
    event("accepted")
    for name in loaded.sections():
        check_ranges(getattr(loaded, name), name)  # every accepted number is inside its range


@FUZZ
@given(doc=sections, used=st.lists(st.sampled_from(ALL), min_size=1, max_size=4, unique=True))
def test_a_config_file_loads_or_is_refused_in_one_line(tmp_path_factory, doc, used):
    path = tmp_path_factory.mktemp("cfg") / "fuzz.yaml"
    path.write_text(yaml.safe_dump(doc, allow_unicode=True), encoding="utf-8")
    _check(load_settings, used, str(path))


@FUZZ
@given(text=st.one_of(st.text(max_size=300), st.binary(max_size=300).map(lambda b: b.decode("latin-1"))))
def test_raw_text_as_a_config_file_loads_or_is_refused_in_one_line(tmp_path_factory, text):
    path = tmp_path_factory.mktemp("raw") / "fuzz.yaml"
    path.write_text(text, encoding="utf-8", errors="surrogatepass")
    _check(load_settings, ALL, str(path))



@FUZZ
@given(items=st.lists(st.tuples(st.one_of(names, st.sampled_from(ALL).flatmap(
           lambda s: st.sampled_from([f"{s}.{f.name}" for f in dataclasses.fields(section_class(s))]))),
           st.one_of(values.map(lambda v: yaml.safe_dump(v, default_flow_style=True).strip()), YAML_TEXT,
                     st.floats(allow_nan=True, allow_infinity=True).map(repr), st.integers().map(str))),
           min_size=1, max_size=4))
def test_set_overrides_load_or_are_refused_in_one_line(items):
    _check(load_settings, ALL, None, [f"{n}={r}" for n, r in items])
