"""Failure messages and exceptions in short categories (bench/failure_reasons.py)."""

from grasp_pipeline.bench.failure_reasons import exception_category, reason_category


def test_failure_reasons_are_short_categories():
    assert reason_category("CLOSE failed: fingers stalled at 12.5 mm but touch no object") == \
        "fingers stalled at N mm but touch no object"
    assert reason_category("PRE_GRASP failed: no grasp candidate can be reached: IK x | y") == \
        "no grasp candidate can be reached"
    assert reason_category("PLACE failed: execution stopped: unexpected robot contact [('a', 'b')]; the arm") == \
        "execution stopped: unexpected robot contact"
    assert reason_category("") == "unspecified"
    assert exception_category("RuntimeError: boom 3") == "RuntimeError"
