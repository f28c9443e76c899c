"""The one serializer: valid JSON from typed results, atomic writes, clear errors."""

import json
import math
import os
from dataclasses import dataclass, field

import numpy as np
import pytest

from grasp_pipeline.report.serialize import (OMIT_IF_NONE, OutputError, check_writable, dumps, to_jsonable,
                                             write_json)
from grasp_pipeline.results import PickResult, RunReport, ScanReport, TrackSummary


@dataclass
class _Inner:
    value: float = math.nan
    arr: np.ndarray = field(default_factory=lambda: np.array([1.0, np.inf, 2.0]))


def test_non_finite_numbers_become_null_and_the_text_is_strict_json():
    text = dumps({"a": math.nan, "b": -math.inf, "c": np.float32(1.5), "d": _Inner(), "e": (1, 2)})
    data = json.loads(text, parse_constant=lambda c: pytest.fail(f"{c} in JSON"))
    assert data == {"a": None, "b": None, "c": 1.5, "d": {"value": None, "arr": [1.0, None, 2.0]}, "e": [1, 2]}


def test_typed_results_serialize_with_their_field_names():
    report = RunReport(scene={"name": "x"}, settings={}, picks=[PickResult(anchor=[0.5, 0.0])],
                       scan=ScanReport(tracks=[TrackSummary(1, "NADIR", 0.1, [0, 0, 0], [1, 1, 1], 0.0, True)]))
    data = to_jsonable(report)
    assert data["picks"][0]["anchor"] == [0.5, 0.0] and data["status"] == "running"
    assert data["scan"]["tracks"][0]["quality"] == "NADIR"


@dataclass(frozen=True)
class _Result:
    status: str
    interrupted_while: str | None = field(default=None, metadata=OMIT_IF_NONE)
    summary: str | None = None
    _private: int = 0


def test_a_field_marked_omit_if_none_is_left_out_while_none():
    assert to_jsonable(_Result("complete")) == {"status": "complete", "summary": None}
    assert list(to_jsonable(_Result("interrupted", "simulating", "s.md"))) == \
        ["status", "interrupted_while", "summary"]


def test_write_json_replaces_a_file_atomically(tmp_path):
    path = tmp_path / "report.json"
    write_json(path, {"run": 1})
    write_json(path, {"run": 2})
    assert json.loads(path.read_text()) == {"run": 2}
    assert [p.name for p in tmp_path.iterdir()] == ["report.json"]  # no temporary left


def test_a_written_report_has_the_permissions_of_any_new_file(tmp_path):
    """0666 less the umask, like the images beside it — not the 0600 of a temporary file."""
    old = os.umask(0o022)
    try:
        write_json(tmp_path / "shared.json", {"run": 1})
        os.umask(0o077)
        write_json(tmp_path / "private.json", {"run": 1})
    finally:
        os.umask(old)
    assert (tmp_path / "shared.json").stat().st_mode & 0o777 == 0o644
    assert (tmp_path / "private.json").stat().st_mode & 0o777 == 0o600


def test_a_failed_write_keeps_the_previous_file_and_names_the_path(tmp_path, monkeypatch):
    path = tmp_path / "report.json"
    write_json(path, {"run": 1})

    def full_disk(*a, **k):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "fsync", full_disk)
    with pytest.raises(OutputError, match="report.json.*No space left"):
        write_json(path, {"run": 2})
    assert json.loads(path.read_text()) == {"run": 1}
    assert [p.name for p in tmp_path.iterdir()] == ["report.json"]


def test_unwritable_outputs_are_found_before_any_work(tmp_path):
    with pytest.raises(OutputError, match="is a directory"):
        check_writable(tmp_path)
    blocker = tmp_path / "file"
    blocker.write_text("x")
    with pytest.raises(OutputError, match="cannot write"):
        check_writable(blocker / "sub" / "report.json")
