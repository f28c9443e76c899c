"""``grasp-pipeline bench clutter``: one small round of each protocol, as a user runs it (the
installed console script in a clean environment; real MuJoCo, PCL, OMPL, TOPP-RA), the three
protocols side by side; plus the metrics' arithmetic on synthetic round records."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

from grasp_pipeline.bench import clutter_bench as cb
from grasp_pipeline.bench.clutter_result import ObjectSuccess, RatePair
from grasp_pipeline.bench.figures import StageFailures
from grasp_pipeline.report.serialize import to_jsonable

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from faults import EXE, clean_env  # noqa: E402
SMALL = {"packed": ["--set", "clutter.objects_per_scene=2", "--rerun", "recs"],  # + a recording per round
         "pile": ["--set", "clutter.objects_per_scene=2"],
         "sparse": ["--set", "sim.object_count=[2,2]"]}
REQUIRED = ("protocol", "rounds", "objects_placed", "attempts", "successes", "gsr", "dr", "seeds",
            "mean", "std", "failures_by_stage", "segmentation", "time_per_attempt_s",
            "time_per_round_s", "success_by_object", "end_reasons", "round_rows", "grasp_bound")


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """The three protocols' 1-round benchmarks, started together (2 cores)."""
    assert EXE.exists(), f"{EXE} is missing: install the package first (make setup)"
    procs = {}
    for protocol, extra in SMALL.items():
        d = tmp_path_factory.mktemp(f"clutter_{protocol}")
        env = clean_env(d)  # (with PYTHONPATH when a source checkout is under test)
        args = [str(EXE), "--log-level", "WARNING", "bench", "clutter", "--protocol", protocol,
                "--rounds", "1", "--seed", "5", "--workers", "1", "--json", "b.json", "--out", "out",
                "--no-progress", *extra]
        procs[protocol] = (d, subprocess.Popen(args, cwd=d, env=env, stdout=subprocess.PIPE,
                                               stderr=subprocess.PIPE, text=True, stdin=subprocess.DEVNULL))
    out = {}
    for protocol, (d, p) in procs.items():
        stdout, stderr = p.communicate(timeout=1200)
        out[protocol] = (d, p.returncode, stdout, stderr)
    return out


def _strict(path: Path) -> dict:
    def refuse(c):
        raise ValueError(f"{path} holds {c}")
    return json.loads(path.read_text(), parse_constant=refuse)


@pytest.mark.parametrize("protocol", list(SMALL))
def test_one_round_gives_the_vgn_metrics(runs, protocol):
    d, rc, stdout, stderr = runs[protocol]
    assert rc == 0 and "Traceback" not in stderr, stderr[-3000:]
    res = _strict(d / "b.json")
    for key in REQUIRED:
        assert key in res, key
    assert res["protocol"] == protocol and res["rounds"] == 1 and res["status"] == "complete"
    assert res["objects_placed"] >= 1 and 1 <= res["attempts"] <= 20
    for key in ("gsr", "dr"):
        assert 0.0 <= res[key] <= 1.0
        assert res["seeds"][0][key] == res[key] and res["mean"][key] == res[key] and res["std"][key] == 0.0
    assert res["gsr"] == round(res["successes"] / res["attempts"], 4)     # (the JSON keeps 4 decimals)
    assert res["dr"] == round(res["successes"] / res["objects_placed"], 4)
    row = res["round_rows"][0]
    assert row["end_reason"] and row["error"] is None
    assert len(row["attempts"]) == res["attempts"]
    assert sum(f["count"] for f in res["failures_by_stage"].values()) == res["attempts"] - res["successes"]
    seg = res["segmentation"]
    assert seg["objects"] == res["objects_placed"] and 0.0 <= seg["correct_rate"] <= 1.0
    assert seg["scored"] >= 1  # the scan's probe frames were scored against the pixel labels
    assert (d / "out" / "summary.md").read_text().count("GIGA") >= (1 if protocol != "sparse" else 0)
    for png in ("rates.png", "objects.png", "failures.png"):
        assert (d / "out" / png).stat().st_size > 5_000
    assert not [p for p in (d / "out").rglob("*.png") if p.name in ("rough.png", "scan.png")]  # (no stage pictures)
    for a in row["attempts"]:  # every failed attempt has its PNGs (paths as the run was given them)
        assert a["success"] or (a["snapshots"] and all((d / p).exists() for p in a["snapshots"]))
    assert f"GSR" in stdout
    _check_gap_to_geometry(res, row, (d / "out" / "summary.md").read_text())


def _check_gap_to_geometry(res, row, summary):
    """Every object placed has its bound and outcome; the picked ones are the successes."""
    from grasp_pipeline.evaluation.grasp_bound import LABELS
    from grasp_pipeline.evaluation.object_outcomes import OUTCOMES

    b, objs = res["grasp_bound"], row["object_outcomes"]
    assert len(objs) == row["objects_placed"] == b["objects"]
    assert sorted(o["name"] for o in objs) == sorted(row["models"])
    assert all(o["label"] in LABELS and o["outcome"] in OUTCOMES for o in objs)
    assert b["picked"] == res["successes"] and sum(b["outcomes"].values()) == b["objects"]
    assert sum(o["attempts"] for o in objs) <= res["attempts"]
    for k in ("top_down", "tilted", "any_side"):
        assert b[f"dr_{k}"] is None or 0.0 <= b[f"dr_{k}"] <= 1.0
    assert b["config"]["max_width_m"] == 0.075
    assert "## Gap to geometry" in summary and "DR against it" in summary


def _round(index, seed, placed, outcomes, model="mug"):
    attempts = [{"object": f"o{k}", "model": model, "success": ok, "wall_s": 10.0, "snapshots": [],
                 **({} if ok else {"stage": stage, "reason": "r", "message": "m"})}
                for k, (ok, stage) in enumerate(outcomes)]
    return {"index": index, "bench_seed": seed, "seed": 100 + index, "objects_placed": placed,
            "models": {f"o{k}": model for k in range(placed)}, "attempts": attempts,
            "successes": sum(ok for ok, _ in outcomes), "end_reason": "table cleared",
            "segmentation": [], "error": None, "timings": {"wall_s": 60.0}}


def test_aggregate_pools_rounds_and_averages_seeds():
    rows = [_round(0, 1, 3, [(True, None), (True, None), (True, None)]),
            _round(1, 2, 4, [(True, None), (False, "CLOSE"), (False, "PRE_GRASP")])]
    res = cb.aggregate(rows, "packed", "builtin", [1, 2], workers=2, wall_time_s=120.0)
    assert (res.attempts, res.successes, res.objects_placed) == (6, 4, 7)
    assert res.gsr == round(4 / 6, 4) and res.dr == round(4 / 7, 4)
    assert [s.gsr for s in res.seeds] == [1.0, round(1 / 3, 4)]
    assert math.isclose(res.mean.gsr, (1.0 + 1 / 3) / 2, abs_tol=1e-4)
    assert math.isclose(res.std.gsr, (1.0 - 1 / 3) / 2, abs_tol=1e-4)
    assert res.mean.dr == 0.625 and isinstance(res.mean, RatePair)
    assert res.failures_by_stage == {"PRE_GRASP": StageFailures(1, {"r": 1}), "CLOSE": StageFailures(1, {"r": 1})}
    assert res.attempts_executed == 5 and res.gsr_executed == 0.8  # PRE_GRASP never moved
    assert res.success_by_object["mug"] == ObjectSuccess(placed=7, attempts=6, picked=4,
                                                         success_rate=round(4 / 6, 4))
    assert res.rounds_per_hour == 60.0
    keys = list(to_jsonable(res))  # the results file's key order: the round rows last
    assert keys[:4] == ["benchmark", "protocol", "objects", "seed_list"] and keys[-1] == "round_rows"


def test_aggregate_rates_the_picks_against_each_geometric_bound(tmp_path):
    from grasp_pipeline.bench.clutter_plots import write_summary

    rows = [_round(0, 1, 3, [(True, None), (False, "CLOSE")]), _round(1, 1, 2, [(True, None)])]
    rows[0]["object_outcomes"] = [
        {"name": "o0", "label": "top_down", "label_width_only": "top_down", "outcome": "picked"},
        {"name": "o1", "label": "tilted", "label_width_only": "tilted", "outcome": "attempted_failed",
         "stage": "CLOSE", "reason": "r"},
        {"name": "o2", "label": "top_down", "label_width_only": "top_down", "outcome": "never_proposed",
         "why": "grasp source 'geometric' proposed no grasp"}]
    rows[1]["object_outcomes"] = [
        {"name": "o0", "label": "none", "label_width_only": "any_side", "outcome": "picked"},
        {"name": "o1", "label": "any_side", "label_width_only": "any_side", "outcome": "not_seen"}]
    res = cb.aggregate(rows + [_round(2, 1, 1, [])], "pile", "builtin", [1], workers=1, wall_time_s=60.0)
    b = res.grasp_bound  # (the third round has no object rows: counted nowhere)
    assert b["objects"] == 5 and b["picked"] == 2 == res.successes
    assert (b["dr_top_down"], b["dr_tilted"], b["dr_any_side"]) == (0.5, round(1 / 3, 4), 0.25)
    assert b["dr_width_only"]["any_side"] == 0.4 and b["picked_outside_bound"] == 1
    assert b["never_proposed_reasons"] == {"grasp source 'geometric' proposed no grasp": 1}
    assert res.dr == round(2 / 6, 4)  # the existing figures unchanged
    text = write_summary({**to_jsonable(res), "out_dir": str(tmp_path)}, tmp_path / "summary.md").read_text()
    assert "## Gap to geometry" in text and "| top_down (from straight above) | 2 (40.0 %) | 50.0 % |" in text
    assert "| none | 1 | 0 | 0 | 0 | 0 | 0 | 0 | 0 | 1 |" in text


def test_bad_protocol_and_object_folder_are_refused_before_any_round(tmp_path):
    from grasp_pipeline.objects.model import MeshError

    with pytest.raises(ValueError, match="protocol"):
        cb.run_clutter_benchmark(protocol="heap", rounds=1, json_path=None, out_dir=tmp_path)
    with pytest.raises(MeshError):
        cb.run_clutter_benchmark(protocol="packed", objects=str(tmp_path / "nowhere"), rounds=1,
                                 out_dir=tmp_path)


def test_rerun_writes_one_readable_recording_per_round(runs):
    from grasp_pipeline.report.rerun_summary import summarize_recording

    d, rc, _, stderr = runs["packed"]
    assert rc == 0, stderr[-3000:]
    row = _strict(d / "b.json")["round_rows"][0]
    name = f"seed_5_round_000_scene_{row['seed']}.rrd"
    assert row["recording"] == str(Path("recs") / name)
    assert sorted(p.name for p in (d / "recs").iterdir()) == [name]
    s = summarize_recording(d / "recs" / name)
    assert s["/timeline/picks"].logs == len(row["attempts"])
    assert "scan_done" in s["/timeline/stages"].texts and s["/world/camera"].logs >= 3


def test_the_settings_are_read_once_so_an_edit_during_the_run_cannot_break_its_summary(tmp_path, monkeypatch):
    """The run reads its parameter sets before the first round; a configuration file edited
    (here: unreadable) while the rounds run does not stop the JSON and summary being written."""
    real, calls = cb.clutter_settings, []

    def settings(overrides=(None, ())):
        calls.append(overrides)
        if len(calls) > 1:
            raise RuntimeError("config/sim.yaml was edited during the run")
        return real(overrides)

    monkeypatch.setattr(cb, "clutter_settings", settings)
    monkeypatch.setattr(cb, "run_jobs", lambda *args, **kwargs: ([], False))
    json_path = tmp_path / "clutter.json"
    result = cb.run_clutter_benchmark("sparse", rounds=1, json_path=json_path,
                                      out_dir=tmp_path / "out", progress=False)
    assert len(calls) == 1 and result.status == "complete"
    assert json.loads(json_path.read_text())["rounds_requested"] == 1


def _moves(result) -> list:
    """What each round did: its seed, every attempt's object, outcome and message, its
    simulated seconds."""
    return [(r["seed"], [(a["object"], a["success"], a.get("message")) for a in r["attempts"]],
             r["timings"].get("run_sim_s")) for r in to_jsonable(result)["round_rows"]]


def test_rounds_in_one_worker_are_the_rounds_of_fresh_processes(tmp_path):
    """Two rounds (one object each) run by one worker process one after the other make the
    same moves, attempt for attempt and to the simulated second, as each round in a process of
    its own."""
    kwargs = dict(protocol="sparse", rounds=2, seeds=(7,), json_path=None, progress=False,
                  overrides=(None, ("sim.object_count=[1,1]",)))
    fresh = cb.run_clutter_benchmark(out_dir=tmp_path / "fresh", jobs_per_worker=1, **kwargs)
    reused = cb.run_clutter_benchmark(out_dir=tmp_path / "reused", jobs_per_worker=2, **kwargs)
    assert fresh.status == reused.status == "complete"
    assert sum(len(m[1]) for m in _moves(fresh)) >= 2
    assert _moves(reused) == _moves(fresh)
