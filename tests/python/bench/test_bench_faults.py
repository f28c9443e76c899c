"""``bench clutter`` and ``bench grasp`` interrupted in each phase, as a user interrupts them: Ctrl-C
(SIGINT to the whole process group) or ``kill`` (SIGTERM to the command), at the start of
loading the objects / generating the scenes, of a round's simulation, of writing the results
(:mod:`faults` signals at the start of the named function, in real processes). What is left on
disk is checked: the benchmark JSON is valid and says ``interrupted`` and in which phase, the
interrupted round's own report says so too, and no temporary file or output marker remains.
Also: a benchmark whose every round timed out exits 1 with status ``failed``.

The commands run side by side (a module fixture) to keep the wall time down."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from faults import clean_env, fault_env, leftovers, start  # noqa: E402

CLUTTER = ["--log-level", "WARNING", "bench", "clutter", "--rounds", "1", "--seed", "3", "--json",
           "b.json", "--out", "out", "--no-progress"]
GRASP = ["--log-level", "WARNING", "bench", "grasp", "--scenes", "1", "--seed", "142", "--json",
         "b.json", "--out", "out", "--no-progress", "--set", "sim.object_count=[1,1]"]
SPARSE = ["--protocol", "sparse", "--set", "sim.object_count=[1,1]"]

#: name: (arguments, the function whose start is interrupted, signal, to whom, phase in the JSON)
CASES = {
    "clutter-loading": (CLUTTER + ["--protocol", "packed", "--objects", "builtin"],
                        "grasp_pipeline.objects.catalog:object_set", "SIGTERM", "main",
                        "loading the objects"),
    "clutter-simulating": (CLUTTER + SPARSE, "grasp_pipeline.app.run_loop:_stages", "SIGINT", "group",
                           "simulating"),
    "clutter-writing": (CLUTTER + SPARSE + ["--round-timeout", "1"],
                        "grasp_pipeline.bench.clutter_plots:write_plots", "SIGTERM", "main",
                        "writing the plots and summary"),
    "grasp-generating": (GRASP, "grasp_pipeline.bench.grasp_bench:_object_count", "SIGINT", "group",
                         "generating the scenes"),
    "grasp-simulating": (GRASP, "grasp_pipeline.app.run_loop:_stages", "SIGTERM", "main", "simulating"),
    "grasp-writing": (GRASP + ["--scene-timeout", "1"], "grasp_pipeline.bench.grasp_plots:write_plots",
                      "SIGINT", "group", "writing the plots and summary"),
}


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    procs = {}
    for name, (args, where, sig, target, _) in CASES.items():
        d = tmp_path_factory.mktemp(name)
        procs[name] = (d, start(args, d, clean_env(d, fault_env(d, where, sig, target))))
    d = tmp_path_factory.mktemp("all-time-out")
    procs["all-time-out"] = (d, start(CLUTTER + SPARSE + ["--round-timeout", "1"], d, clean_env(d)))
    out = {}
    for name, (d, p) in procs.items():
        try:
            stdout, stderr = p.communicate(timeout=600)
        except subprocess.TimeoutExpired:
            p.kill()
            stdout, stderr = p.communicate()
        out[name] = (d, p.returncode, stdout, stderr)
    return out


def _strict(path: Path) -> dict:
    def refuse(c):
        raise ValueError(f"{path} holds {c}")
    return json.loads(path.read_text(), parse_constant=refuse)


@pytest.mark.parametrize("name", list(CASES))
def test_an_interrupted_benchmark_leaves_a_json_that_says_when(runs, name):
    d, rc, stdout, stderr = runs[name]
    assert (d / "fault_fired").exists(), f"the fault did not fire\n{stderr[-3000:]}"
    assert rc == 130 and "Traceback" not in stderr, f"rc {rc}\n{stderr[-3000:]}"
    res = _strict(d / "b.json")
    assert res["status"] == "interrupted" and res["interrupted_while"] == CASES[name][4], res.get("status")
    assert leftovers(d) == []
    if CASES[name][4] == "simulating":  # the interrupted round / scene wrote its own report
        reports = list((d / "out").rglob("report.json"))
        assert len(reports) == 1, stderr[-3000:]
        assert _strict(reports[0])["status"] == "interrupted"
    if CASES[name][4] == "writing the plots and summary":  # every round had timed out before
        assert res["status_note"].startswith("1 of 1 ") and "Timeout x1" in res["status_note"]


def test_a_benchmark_whose_every_round_timed_out_fails(runs):
    d, rc, stdout, stderr = runs["all-time-out"]
    assert rc == 1, f"rc {rc}\n{stderr[-3000:]}"
    res = _strict(d / "b.json")
    assert res["status"] == "failed" and res["rounds_failed"] == 1
    assert res["status_note"] == "1 of 1 rounds did not run to their end (Timeout x1)"
    assert stdout.startswith("STATUS FAILED: 1 of 1 rounds")
    assert "did not run to their end" in (d / "out" / "summary.md").read_text()
    assert leftovers(d) == []


def test_rounds_and_scenes_that_did_not_run_make_the_status():
    from grasp_pipeline.bench.clutter_bench import run_status
    from grasp_pipeline.bench.grasp_bench import _status

    ok, timeout, died = {"error_category": None}, {"error_category": "Timeout"}, {"error_category": "WorkerDied"}
    assert run_status([ok, ok], False) == ("complete", "")
    assert run_status([ok, timeout, died], False) == (
        "partial", "2 of 3 rounds did not run to their end (Timeout x1, WorkerDied x1)")
    assert run_status([timeout, timeout], False)[0] == "failed"
    assert run_status([ok], True)[0] == "interrupted" and run_status([], False)[0] == "complete"
    raised = {"error": "ValueError: bad"}
    assert _status([{"error": None}, raised], False) == ("partial", "1 of 2 scenes did not run to their end (ValueError x1)")
    assert _status([raised], False)[0] == "failed"
