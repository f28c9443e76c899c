"""Parameter files and ``--set`` values under bad input: a huge file, a device, a YAML "billion
laughs" and too many aliases are refused at once with one short line; values in messages are
cut; odd keys give errors, not tracebacks."""

from __future__ import annotations

import time

import pytest

from grasp_pipeline.config import MAX_CONFIG_BYTES, MAX_YAML_ALIASES, parse_yaml, read_yaml
from grasp_pipeline.exceptions import ConfigError
from grasp_pipeline.settings import load_settings

LAUGHS = ("lift_height_m: [&a [1, 1, 1, 1, 1, 1, 1, 1, 1],\n"
          + "".join(f"  &{n} [" + ", ".join([f"*{p}"] * 9) + "],\n" for p, n in zip("abcdefg", "bcdefgh"))
          + "  [" + ", ".join(["*h"] * 9) + "]]\n")


def _refused(fn, *args) -> str:
    t0 = time.perf_counter()
    with pytest.raises(ConfigError) as info:
        fn(*args)
    assert time.perf_counter() - t0 < 5.0
    msg = str(info.value)
    assert "\n" not in msg and len(msg) < 400, msg
    return msg


def test_a_huge_config_file_is_refused_before_it_is_read(tmp_path):
    big = tmp_path / "big.yaml"
    with big.open("wb") as fh:  # 50 MB, sparse: nothing to read if the size is checked first
        fh.truncate(50_000_000)
    msg = _refused(load_settings, ("grasp",), str(big))
    assert "big.yaml is 50.0 MB" in msg and f"{MAX_CONFIG_BYTES // 1000} kB" in msg


def test_a_device_or_a_folder_is_not_a_config_file(tmp_path):
    assert "not a regular file" in _refused(read_yaml, "/dev/zero")
    assert "is a directory" in _refused(read_yaml, tmp_path)


def test_a_billion_laughs_file_or_value_is_refused_at_once(tmp_path):
    f = tmp_path / "laughs.yaml"
    f.write_text("grasp:\n  " + LAUGHS.replace("\n  ", "\n    "))
    assert "more than 100000 values once its aliases are expanded" in _refused(load_settings, ("grasp",), str(f))
    value = LAUGHS.split(": ", 1)[1].replace("\n", " ")
    assert "--set 'grasp.lift_height_m'" in _refused(load_settings, ("grasp",), None,
                                                       [f"grasp.lift_height_m={value}"])


def test_aliases_are_limited_and_recursive_values_refused():
    many = "[&a 1, " + ", ".join(["*a"] * (MAX_YAML_ALIASES + 1)) + "]"
    assert f"more than {MAX_YAML_ALIASES} YAML aliases" in _refused(parse_yaml, many, "x")
    assert "values once its aliases are expanded" in _refused(parse_yaml, "&a [*a]", "x")
    assert parse_yaml("a: &x 1\nb: *x\n", "x") == {"a": 1, "b": 1}  # a few aliases are fine


def test_values_in_messages_are_cut(tmp_path):
    msg = _refused(load_settings, ("grasp",), None, ["grasp.lift_height_m=" + "9" * 100_000 + "x"])
    assert "grasp.lift_height_m" in msg and "more characters" not in msg and len(msg) < 200
    msg = _refused(load_settings, ("grasp",), None, ["grasp.approach_backoffs_m=[" + ",".join(["0.01"] * 5000) + ",9]"])
    assert "grasp.approach_backoffs_m[5000] = 9" in msg


def test_yaml_errors_are_one_line_with_the_place(tmp_path):
    f = tmp_path / "bad.yaml"
    f.write_text("grasp:\n  lift_height_m: [0.1,\n")
    assert "(line 3, column 1)" in _refused(read_yaml, f)
    assert "could not determine a constructor" in _refused(
        load_settings, ("grasp",), None, ["grasp.lift_height_m=!!python/object:os.system 1"])


@pytest.mark.parametrize("text, words", [
    ("grasp:\n  1: 2\n  lift_height_m: 0.1\n", "unknown parameter(s) '1'"),
    ("1: {}\n", "unknown config section 1"),
    ("grasp: [1, 2]\n", "must be a mapping"),
    ("grasp:\n  lift_height_m: {a: 1}\n", "cannot use it as a number"),
    ("grasp:\n  closer_look: 1\n", "unknown parameter(s) closer_look"),
    ("scan:\n  closer_look_rules: {wide: 1}\n", "cannot use it as a list"),
])
def test_odd_keys_and_values_are_errors_not_tracebacks(tmp_path, text, words):
    f = tmp_path / "odd.yaml"
    f.write_text(text)
    assert words in _refused(load_settings, ("grasp", "scan"), str(f))


def test_a_file_read_again_gives_its_own_mapping_and_an_edited_file_its_new_values(tmp_path):
    f = tmp_path / "p.yaml"
    f.write_text("a: 1\nb: [1, 2]\n")
    first = read_yaml(f)
    first["b"].append(3)  # the caller's copy: the next read does not see it
    assert read_yaml(f) == {"a": 1, "b": [1, 2]}
    f.write_text("a: 2\nb: [1, 2]\n")
    assert read_yaml(f) == {"a": 2, "b": [1, 2]}
    f.write_text("- 1\n")
    with pytest.raises(ConfigError, match="must hold a mapping"):
        read_yaml(f)
    with pytest.raises(ConfigError, match="must hold a mapping"):  # (not remembered as good)
        read_yaml(f)
