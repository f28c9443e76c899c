"""The figures the benchmark results are made of (bench/figures.py)."""

import math

from grasp_pipeline.bench.figures import StageFailures, Stats, failures_by_stage, rate, stats


def test_stats_of_the_finite_values_and_none_without_any():
    assert stats([1.0, None, math.nan, 3.0, math.inf, 2.0]) == Stats(n=3, median=2.0, p90=2.8, mean=2.0, max=3.0)
    assert stats([]) == Stats(n=0, median=None, p90=None, mean=None, max=None)
    assert rate(1, 3) == 0.3333 and rate(0, 0) is None


def test_failures_by_stage_in_pipeline_order_and_reasons_by_frequency():
    rows = [{"picked": False, "stage": "PLACE", "reason": "a"},
            {"picked": False, "stage": "CLOSE", "reason": "b"},
            {"picked": False, "stage": "CLOSE", "reason": "c"},
            {"picked": False, "stage": "CLOSE", "reason": "c"},
            {"picked": True}]
    out = failures_by_stage(rows)
    assert list(out) == ["CLOSE", "PLACE"]
    assert out["CLOSE"] == StageFailures(count=3, reasons={"c": 2, "b": 1})
    assert list(out["CLOSE"].reasons) == ["c", "b"]
