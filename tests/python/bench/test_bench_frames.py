"""The frames-on-demand comparison's pure parts and the real-time factors of bench grasp
(the full runs are benchmarks, not tests)."""

from grasp_pipeline.bench.frames_bench import compare_outcomes, object_outcomes
from grasp_pipeline.bench.grasp_aggregate import real_time_factors
from grasp_pipeline.bench.grasp_result import RealTimeFactors, strip_timings


def _result(picked_b: bool, stage_b=None):
    rows = [{"name": "a", "picked": True, "attempts": 1},
            {"name": "b", "picked": picked_b, "attempts": 1, "stage": stage_b, "reason": "r" if stage_b else None}]
    return {"scene_rows": [{"index": 3, "seed": 77, "object_rows": rows}]}


def test_object_outcomes_are_keyed_by_scene_and_object():
    out = object_outcomes(_result(True))
    assert set(out) == {(3, "a"), (3, "b")}
    assert out[(3, "a")]["picked"] and out[(3, "a")]["seed"] == 77


def test_identical_outcomes_have_no_differences():
    assert compare_outcomes(_result(True), _result(True)) == []


def test_a_changed_outcome_is_listed_with_both_sides():
    diffs = compare_outcomes(_result(True), _result(False, "CLOSE"))
    assert len(diffs) == 1
    d = diffs[0]
    assert (d["scene"], d["seed"], d["object"]) == (3, 77, "b")
    assert d["continuous"]["picked"] and not d["on_demand"]["picked"]
    assert d["on_demand"]["stage"] == "CLOSE"


def test_real_time_factors_are_ratios_of_sums():
    records = [{"timings": {"wall_s": 10.0, "run_sim_s": 100.0, "picks_s": 5.0, "picks_sim_s": 80.0}},
               {"timings": {"wall_s": 30.0, "run_sim_s": 100.0, "picks_s": 15.0, "picks_sim_s": 80.0}},
               {"timings": {"wall_s": 3.0}}]  # a scene that raised: no simulated time
    assert real_time_factors(records) == RealTimeFactors(run=5.0, pick_loop=8.0)
    assert real_time_factors([]) == RealTimeFactors(run=None, pick_loop=None)


def test_real_time_factors_are_timings_for_the_determinism_checks():
    assert "real_time_factor" not in strip_timings({"real_time_factor": {"run": 3.0}, "x": 1})
