"""The eval report's figures: Wilson intervals, groups, failure reasons."""

import pytest

from grasp_pipeline.learning.eval_report import figures, summary_markdown, wilson_interval

TEMPLATE = "pick up the {object} and put it in the tray"


def test_wilson_interval_known_values():
    assert wilson_interval(0, 1) == [0.0, 0.7935]
    assert wilson_interval(5, 10) == pytest.approx([0.2366, 0.7634], abs=1e-4)
    assert wilson_interval(50, 50) == pytest.approx([0.9287, 1.0], abs=1e-4)
    assert wilson_interval(0, 0) == [0.0, 1.0]


def _row(i, task, model, ok, stage="", where="in the tray"):
    return {"index": i, "scene_seed": i, "task": task, "target_model": model, "success": ok,
            "failed_stage": stage, "target_state": where, "failure_reason": "" if ok else "x",
            "steps": 10 * (i + 1), "wall_s": 1.0 + i, "sim_s": 2.0, "video": None, "error": None}


def test_figures_group_by_task_word_and_object():
    rows = [_row(0, "pick up the red cube and put it in the tray", "cube", True),
            _row(1, "pick up the red cylinder and put it in the tray", "cylinder", False, "GRASP", "on the table"),
            _row(2, "pick up the blue cube and put it in the tray", "cube", False, "TIME_LIMIT", "held up")]
    f = figures(rows, TEMPLATE)
    assert f["successes"] == 1 and f["success_rate"] == pytest.approx(1 / 3, abs=1e-4)
    assert f["by_task_word"]["red"]["episodes"] == 2 and f["by_task_word"]["red"]["successes"] == 1
    assert f["by_object"]["cube"] == {"episodes": 2, "successes": 1, "success_rate": 0.5,
                                      "ci95": wilson_interval(1, 2)}
    assert f["failure_reasons"] == {"GRASP: the target is on the table": 1, "TIME_LIMIT: the target is held up": 1}
    assert f["steps_per_episode"] == [10, 20, 30] and f["mean_steps"] == 20.0
    report = {"policy": "p", "protocol": "sparse", "objects": "builtin", "status": "complete",
              "episodes_finished": 3, "episodes_requested": 3, "seed": 0, "wall_s": 1.0, **f, "episodes": rows}
    md = summary_markdown(report)
    assert "success rate **0.33**" in md and "| cube | 2 | 1 | 0.50 |" in md


def test_a_summary_without_finished_episodes_says_n_a():
    report = {"policy": "p", "protocol": "sparse", "objects": "builtin", "status": "interrupted",
              "episodes_finished": 0, "episodes_requested": 2, "seed": 0, "wall_s": 1.0, "episodes": []}
    md = summary_markdown(report)
    assert "success rate **n/a**" in md and "mean steps n/a, median n/a per episode" in md
    assert "None" not in md
