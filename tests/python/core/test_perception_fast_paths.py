"""The fast paths of the per-frame perception core give the same results as the plain ones.

- The scene filter packs contiguous float32 frames block by block (all-valid blocks are
  copied without the per-row compaction, and the row index array is only written after the
  first invalid row); float64 and strided frames always take the row-by-row path. With
  invalid rows (NaN/Inf, out of range) scattered through the frame, every path must give the
  same labels, planes and clusters.
- method.md §4's two-pass estimation prepares each cluster once and finishes it twice; its second
  pass must equal a full estimate_object() call with the tracker's prior.
"""

import numpy as np
import pytest

from grasp_pipeline import _core
from grasp_pipeline.perception import synthetic as syn


@pytest.fixture(scope="module")
def frame_with_invalid_rows():
    """The benchmark frame with NaN, Inf and out-of-range rows in some 256-row blocks."""
    pts, _ = syn.tabletop_frame(seed=0)
    pts = pts.copy()
    rng = np.random.default_rng(7)
    rows = rng.choice(len(pts), size=500, replace=False)
    pts[rows[:200], 0] = np.nan
    pts[rows[200:300], 2] = np.inf
    pts[rows[300:400], 1] = 5000.0  # beyond max_abs_coordinate_m (1000 m)
    pts[-1] = np.nan  # the last row of the last (partial) block
    pts[:256, 1] = np.nan  # one whole invalid block
    return pts


def _filter_outputs(points):
    res = _core.SceneFilter(_core.SceneFilterParams()).process(points)
    planes = [(p.count_whole, p.removed, p.subsample_inliers, tuple(p.plane.n), p.plane.c)
              for p in res.planes]
    return (np.asarray(res.labels).copy(), planes, res.num_valid, res.num_invalid,
            res.num_out_of_range, res.num_candidates, list(res.cluster_ids))


def test_float32_fast_path_equals_the_row_by_row_paths(frame_with_invalid_rows):
    pts = frame_with_invalid_rows
    fast = _filter_outputs(pts)
    as_double = _filter_outputs(pts.astype(np.float64))
    wide = np.zeros((len(pts), 4), dtype=np.float32)
    wide[:, :3] = pts
    strided = _filter_outputs(wide[:, :3])  # row stride 4: the row-by-row path
    for other in (as_double, strided):
        assert np.array_equal(fast[0], other[0])
        assert fast[1:] == other[1:]
    labels = fast[0]
    # counts and invalid labels also agree with numpy
    invalid = ~np.isfinite(pts).all(axis=1) | (np.abs(pts) > 1000.0).any(axis=1)
    assert fast[3] == int(invalid.sum()) and fast[2] == len(pts) - int(invalid.sum())
    assert np.array_equal(labels == _core.LABEL_INVALID, invalid)
    assert len(fast[6]) == 3  # still three objects


def test_all_valid_frame_labels_match_the_row_by_row_path():
    pts, _ = syn.tabletop_frame(seed=1)
    fast = _filter_outputs(pts)
    slow = _filter_outputs(pts.astype(np.float64))
    assert np.array_equal(fast[0], slow[0]) and fast[1:] == slow[1:]


def test_second_pass_equals_a_full_estimate_with_the_prior():
    pts, T = syn.tabletop_frame(seed=2)
    per = _core.Perception(_core.SceneFilterParams(), _core.ObbParams())
    for i in range(3):  # tracks with smoothed theta
        per.process(pts, T[:3, 3], i / 30.0)
    fr = per.process(pts, T[:3, 3], 3 / 30.0)
    labels = np.asarray(fr.filter.labels)
    plane = fr.filter.table
    clusters = [pts[labels == k].astype(np.float64) for k in fr.filter.cluster_ids]
    params = _core.ObbParams()
    results = _core.estimate_with_priors(clusters, plane, params, per.tracker, band=fr.filter.band)
    centres = [_core.estimate_object(c, plane, params, band=fr.filter.band).estimate.center
               for c in clusters]
    d_min = min(np.linalg.norm(a - b) for i, a in enumerate(centres) for b in centres[i + 1:])
    for c, centre, r in zip(clusters, centres, results):
        prior = per.tracker.prior_theta(centre, params.assoc_gate_frac * d_min)
        assert prior is not None
        ref = _core.estimate_object(c, plane, params, theta_prev=prior, band=fr.filter.band).estimate
        e = r.estimate
        assert e.theta_rad == ref.theta_rad and e.width_m == ref.width_m
        assert e.perp_width_m == ref.perp_width_m and e.height_m == ref.height_m
        assert np.array_equal(e.center, ref.center) and np.array_equal(e.R_box, ref.R_box)
        assert np.array_equal(e.extents, ref.extents) and e.anisotropy == ref.anisotropy
        assert np.array_equal(e.pca.center, ref.pca.center) and e.notes == ref.notes
