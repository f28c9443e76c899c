"""``grasp-pipeline bench grasp`` on a small benchmark: two real scenes (MuJoCo, the PCL core,
OMPL, TOPP-RA; no mocks) in two spawned worker processes, through the CLI. The JSON is checked
for its keys and for sane values, the plots and the summary for being written.

Seed 142 was chosen because both of its scenes have one object each (fast); the test asserts
that, so a change of the scene generator shows up here instead of as a slow test."""

import json
import math

import pytest

from grasp_pipeline.bench import grasp_bench as gb
from grasp_pipeline.bench.grasp_aggregate import aggregate
from grasp_pipeline.bench.seeds import scene_seed
from grasp_pipeline.cli import main
from grasp_pipeline.report.serialize import to_jsonable
from grasp_pipeline.sim.scenes import random_scene

SEED = 142
SCENES = 2
REQUIRED_KEYS = ("scenes", "objects", "success_rate", "failures_by_stage", "accuracy",
                 "accuracy_oblique", "scan_success_rate", "time_per_scene_s", "time_per_stage_s",
                 "wall_time_s", "scenes_per_minute", "workers", "scene_rows", "scan_improvement")
METRICS = ("center_mm", "width_mm", "height_mm", "yaw_deg")


def _walk_numbers(x):
    if isinstance(x, bool) or x is None or isinstance(x, str):
        return
    if isinstance(x, (int, float)):
        yield x
    elif isinstance(x, dict):
        for v in x.values():
            yield from _walk_numbers(v)
    elif isinstance(x, list):
        for v in x:
            yield from _walk_numbers(v)


def test_the_chosen_scenes_are_small():
    sizes = [len(random_scene(scene_seed(SEED, i)).objects) for i in range(SCENES)]
    assert max(sizes) <= 2, sizes


@pytest.fixture(scope="module")
def bench(tmp_path_factory):
    out = tmp_path_factory.mktemp("bench_grasp")
    json_path = out / "bench.json"
    rc = main(["--log-level", "WARNING", "bench", "grasp", "--scenes", str(SCENES), "--seed", str(SEED),
               "--workers", "2", "--json", str(json_path), "--out", str(out), "--no-progress"])
    assert rc == 0
    text = json_path.read_text()
    assert "NaN" not in text and "Infinity" not in text
    return json.loads(text), out


def test_json_has_the_keys_and_sane_values(bench):
    res, _out = bench
    for key in REQUIRED_KEYS:
        assert key in res, key
    assert res["scenes"] == SCENES and res["workers"] == 2
    assert res["objects"] >= SCENES
    for key in ("success_rate", "scan_success_rate"):
        assert 0.0 <= res[key] <= 1.0, key
    for n in _walk_numbers(res):
        assert math.isfinite(n)
    for acc in (res["accuracy"], res["accuracy_oblique"]):
        for m in METRICS:
            s = acc[m]
            assert {"median", "p90", "n"} <= set(s)
            if s["n"]:
                assert 0.0 <= s["median"] <= s["p90"]
    assert res["wall_time_s"] > 0 and res["scenes_per_minute"] > 0
    assert res["time_per_scene_s"]["median"] > 0
    assert {"rough_view_s", "wall_s"} <= set(res["time_per_stage_s"])
    # the failures add up to the objects not picked
    assert sum(f["count"] for f in res["failures_by_stage"].values()) == res["objects"] - res["picked"]


def test_scene_rows_are_sorted_seeded_and_every_failure_has_a_stage(bench):
    res, _out = bench
    rows = res["scene_rows"]
    assert [r["index"] for r in rows] == list(range(SCENES))
    assert [r["seed"] for r in rows] == [scene_seed(SEED, i) for i in range(SCENES)]
    assert sum(r["objects"] for r in rows) == res["objects"]
    for r in rows:
        assert {"seed", "objects", "picks", "errors"} <= set(r)
        assert 0 <= r["picks"] <= r["objects"] == len(r["object_rows"])
        for o in r["object_rows"]:
            if not o["picked"]:
                assert o["stage"] and o["reason"], o
        if r["picks"] < r["objects"]:
            assert r["errors"]


def test_plots_and_summary_are_written(bench):
    res, out = bench
    for name in ("errors", "success", "failures", "timing"):
        png = out / res["plots"][name]
        assert png.suffix == ".png" and png.stat().st_size > 10_000, png
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    md = (out / "summary.md").read_text()
    assert "oblique" in md and "NADIR" in md and "errors.png" in md


def test_a_scene_that_raises_is_a_failed_scene_not_a_crash(tmp_path):
    rec = gb.run_scene(0, -1, tmp_path)  # a negative seed: the scene generator raises
    assert rec["error"] and rec["error"].startswith("ValueError")
    res = aggregate([rec], seed=0, workers=1, wall_time_s=1.0)
    assert res.scenes == 1 and res.scenes_failed == 1 and res.scene_rows[0].errors
    assert res.success_rate is None  # (no objects known: no rate, not NaN)


def test_objects_of_a_scene_that_raised_fail_at_stage_scene():
    seed = scene_seed(SEED, 0)
    rec = gb.scene_record(0, seed, gb._spec_objects(seed), None, error="RuntimeError: boom 3", wall_s=2.0)
    res = aggregate([rec], seed=SEED, workers=1, wall_time_s=2.0)
    assert res.objects >= 1 and res.success_rate == 0.0
    assert res.failures_by_stage["SCENE"].reasons == {"RuntimeError": res.objects}
    assert res.targets["pick success"].value == 0.0 and res.targets["pick success"].met is False


def test_the_result_json_keeps_the_files_key_order():
    """The typed result writes the keys the results files have always had, in their order: the
    figures first, the run's facts, then the long per-scene rows last."""
    seed = scene_seed(SEED, 0)
    rec = gb.scene_record(0, seed, gb._spec_objects(seed), None, error="RuntimeError: boom 3", wall_s=2.0)
    keys = list(to_jsonable(aggregate([rec], seed=SEED, workers=1, wall_time_s=2.0)))
    assert keys[:5] == ["benchmark", "seed", "scene_seed_rule", "scenes", "scenes_failed"]
    assert keys[-4:] == ["scenes_finished", "warnings", "summary", "scene_rows"]  # (no plots yet)
    assert "interrupted_while" not in keys and keys.index("targets") == keys.index("workers") + 1
