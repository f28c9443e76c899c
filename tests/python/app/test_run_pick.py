"""``grasp-pipeline run --pick DESCRIPTION`` as a user runs it (installed console script, clean
environment): descriptions resolved against the perceived objects after the scan, the objects
picked in the order given; refusals end the run with a one-line error and a valid report."""

from __future__ import annotations

import numpy as np
import pytest

from .test_entry_points import run_cli, strict_json

#: The reference scene (method.md §8): blue cube (0.56, -0.03), red cube (0.46, -0.10), green
#: cylinder (0.52, 0.09); the red cube is nearest to the robot base.
REFERENCE = {"blue cube": (0.56, -0.03), "red cube": (0.46, -0.10), "green cylinder": (0.52, 0.09)}


def _error_line(res) -> str:
    lines = [ln for ln in res.stderr.splitlines() if ln.strip()]
    assert lines and lines[-1].startswith("error: "), res.stderr[-2000:]
    return lines[-1]


def test_run_pick_resolves_and_picks_in_order(tmp_path):
    res = run_cli(["run", "--pick", "the green can", "--pick", "the nearest box", "--no-video",
                   "--out", "out"], None, tmp_path)
    assert res.returncode == 0, res.stderr[-3000:]
    report = strict_json(tmp_path / "out" / "report.json")
    assert report["status"] == "complete" and report["error"] is None
    resolved = report["resolved"]
    assert [r["description"] for r in resolved] == ["the green can", "the nearest box"]
    assert [r["described"] for r in resolved] == ["the green cylinder", "the red box"]
    for r, truth in zip(resolved, ("green cylinder", "red cube")):   # ground truth checks only
        assert np.hypot(*(np.array(r["center"][:2]) - REFERENCE[truth])) < 0.01
    picks = report["picks"]
    assert len(picks) == 2 and all(p["success"] for p in picks)
    for p, r in zip(picks, resolved):
        assert np.hypot(*(np.array(p["anchor"][:2]) - r["center"][:2])) < 0.01
    assert "'the green can': #" in res.stdout and "the green cylinder at (0.520, 0.090)" in res.stdout


def test_an_ambiguous_description_ends_the_run_with_a_valid_report(tmp_path):
    res = run_cli(["run", "--pick", "the box", "--no-video", "--out", "out"], None, tmp_path)
    assert res.returncode == 1
    line = _error_line(res)
    assert line.startswith("error: AmbiguousDescriptionError: 'the box' fits 2 objects (#")
    assert "seen: #" in line and "red box" in line and "blue box" in line and "green cylinder" in line
    report = strict_json(tmp_path / "out" / "report.json")
    assert report["status"] == "failed" and report["error"] == line[len("error: "):]
    assert report["picks"] == [] and report["resolved"] == [] and report["scan"]["completed"]


@pytest.mark.parametrize("args, words", [
    (["--pick", "the shiny box"], "unknown word(s) 'shiny'; known words: colour: black"),
    (["--pick", "the red box", "--select", "0.5", "0.0"], "cannot be combined with --select"),
    (["--pick", "the red box", "--declutter"], "cannot be combined with --declutter"),
    (["--pick", " "], "an empty description"),
])
def test_bad_descriptions_are_refused_before_the_simulation(args, words, tmp_path):
    res = run_cli(["run", *args, "--no-video", "--out", "out"], "disable", tmp_path)
    assert res.returncode == 2
    errors = [ln for ln in res.stderr.splitlines() if "ERROR" in ln]
    assert len(errors) == 1 and words in errors[0], res.stderr[-2000:]
    assert not (tmp_path / "out").exists()
