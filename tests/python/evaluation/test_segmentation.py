"""Segmentation scoring against per-pixel ground truth (pure functions, synthetic labels)."""

import numpy as np

from grasp_pipeline.evaluation.segmentation import (MIN_VISIBLE_POINTS, ObjectSegmentation,
                                                    score_frame, score_object, summarize)

NONE = -1


def _frame(parts):
    """Concatenate (gt, perceived, n) runs into per-row arrays."""
    gt = np.concatenate([np.full(n, g) for g, _p, n in parts])
    pc = np.concatenate([np.full(n, p) for _g, p, n in parts])
    return gt, pc


def test_one_clean_cluster_is_correct():
    gt, pc = _frame([(0, 5, 100), (NONE, -1, 50)])
    s = score_object(gt, pc, 0, "cube")
    assert s.correct and not (s.merged or s.split or s.missed)
    assert s.purity == 1.0 and s.coverage == 1.0 and s.cluster == 5


def test_two_objects_in_one_cluster_are_merged():
    gt, pc = _frame([(0, 2, 100), (1, 2, 100)])
    for k in (0, 1):
        s = score_object(gt, pc, k, f"o{k}")
        assert s.merged and not s.correct and s.purity == 0.5 and s.coverage == 1.0


def test_an_object_over_two_clusters_is_split():
    gt, pc = _frame([(0, 1, 60), (0, 4, 40)])
    s = score_object(gt, pc, 0, "mug")
    assert s.split and s.parts == 2 and not s.correct and s.coverage == 0.6


def test_a_small_stray_part_keeps_it_correct_but_a_table_skirt_lowers_purity():
    gt, pc = _frame([(0, 1, 95), (0, 3, 5)])
    assert score_object(gt, pc, 0, "box").correct          # 95 % coverage, 1 part
    gt, pc = _frame([(0, 1, 100), (NONE, 1, 20)])            # 20 table points in the cluster
    s = score_object(gt, pc, 0, "box")
    assert s.merged and not s.correct and abs(s.purity - 100 / 120) < 1e-3


def test_unclustered_object_is_missed():
    gt, pc = _frame([(0, -1, 100)])
    s = score_object(gt, pc, 0, "flat")
    assert s.missed and not s.correct and s.cluster is None


def test_score_frame_counts_only_points_above_the_band_and_visible_objects():
    gt, pc = _frame([(0, 1, 100), (0, -1, 100), (1, 2, MIN_VISIBLE_POINTS - 1)])
    above = np.concatenate([np.ones(100, bool), np.zeros(100, bool), np.ones(MIN_VISIBLE_POINTS - 1, bool)])
    scores = score_frame(gt, pc, above, ["a", "b"])
    assert [s.object for s in scores] == ["a"]             # b has too few visible points
    assert scores[0].correct and scores[0].visible == 100  # the band slice does not count


def test_summary_counts_unscored_objects_as_missed():
    ok = ObjectSegmentation("a", 10, 1, 1.0, 1.0, 1, True, False, False, False)
    bad = ObjectSegmentation("b", 10, 1, 0.5, 1.0, 1, False, True, False, False)
    s = summarize([ok, bad], objects=3)
    assert s == {"objects": 3, "scored": 2, "correct": 1, "correct_rate": round(1 / 3, 4),
                 "merged": 1, "split": 0, "missed": 1}
