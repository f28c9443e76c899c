"""Ranking the any-side sampler's grasps: a predicted quality in [0, 1], and near-duplicates.

The score is the weighted mean (weights in ``config/grasp_sampler.yaml``) of

* **coverage**: the worse pad's share of its width on material;
* **antipodality**: how well the seen surfaces at the contacts face the pads (|n·c|);
* **centre**: the closing line's distance from the object's centroid across the approach
  (a grasp far from it lets the object turn in the fingers), 1 at the centroid, 0 at
  ``centre_scale_m`` and beyond;
* **depth**: the same along the approach (a tall object grasped at its very top swings);
* **width**: how close the width is to the narrowest of the object's candidates (1 there, 0
  ``width_scale_m`` wider): closing across a box's faces, not its diagonal;
* **overlap**: the pads' share of their length on the object;
* **tilt**: 1 for top-down; a tilted approach 0.5 falling to 0.3 at the tilt limit (a tilted
  grasp is harder to carry out than a top-down one, but among tilted grasps the tilt that
  fits the object best should win);
* **clearance**: of the hand from the neighbours, 1 from ``hand_clearance_enough_m``;
* **seen**: the share of the fingers' way the cameras have seen.
"""

from __future__ import annotations

import numpy as np

from .candidates import Frames
from .config import SamplerConfig
from .contacts import ContactLimits, Contacts


def score(con: Contacts, frames: Frames, cfg: SamplerConfig, lim: ContactLimits,
          clearance, unknown, idx=None) -> np.ndarray:
    """Scores of the frames ``idx`` (all when None); ``clearance`` / ``unknown`` are per
    index (None: not known yet — left out of the mean)."""
    idx = np.arange(len(frames)) if idx is None else np.asarray(idx)
    terms = [
        (cfg.weight_coverage, con.coverage[idx]),
        (cfg.weight_antipodal, con.antipodal[idx]),
        (cfg.weight_centre, 1.0 - np.clip(con.lateral_m[idx] / cfg.centre_scale_m, 0.0, 1.0)),
        (cfg.weight_depth, 1.0 - np.clip(con.depth_off_m[idx] / (3.0 * cfg.centre_scale_m), 0.0, 1.0)),
        (cfg.weight_width, _narrow(con, idx, cfg.width_scale_m)),
        (cfg.weight_overlap, con.overlap[idx]),
        (cfg.weight_tilt, _upright(frames.tilt_deg[idx], cfg.max_tilt_deg)),
    ]
    if clearance is not None:
        terms.append((cfg.weight_clearance, np.clip(np.asarray(clearance) / cfg.hand_clearance_enough_m, 0.0, 1.0)))
    if unknown is not None:
        terms.append((cfg.weight_unknown, 1.0 - np.clip(np.asarray(unknown), 0.0, 1.0)))
    w = sum(t[0] for t in terms)
    if w <= 0:
        return np.zeros(len(idx))
    return sum(t[0] * t[1] for t in terms) / w


def _upright(tilt_deg: np.ndarray, max_tilt_deg: float) -> np.ndarray:
    from .grasp import TOP_DOWN_TOLERANCE_DEG

    tilted = 0.5 - 0.2 * np.clip(tilt_deg / max(max_tilt_deg, 1.0), 0.0, 1.0)
    return np.where(tilt_deg <= TOP_DOWN_TOLERANCE_DEG, 1.0, tilted)


def _narrow(con: Contacts, idx: np.ndarray, scale_m: float) -> np.ndarray:
    ok = con.code == 0
    w_min = float(con.width_m[ok].min()) if np.any(ok) else float(con.width_m[idx].min())
    return 1.0 - np.clip((con.width_m[idx] - w_min) / scale_m, 0.0, 1.0)


def dedupe(order: np.ndarray, origins: np.ndarray, a: np.ndarray, c: np.ndarray,
           distance_m: float, angle_deg: float) -> list:
    """``order`` (indices, best first) without grasps within ``distance_m`` and ``angle_deg``
    (approach and closing axis) of a better one."""
    cos = np.cos(np.radians(angle_deg))
    kept: list = []
    for k in order:
        if any(np.linalg.norm(origins[k] - origins[j]) < distance_m and a[k] @ a[j] >= cos
               and abs(c[k] @ c[j]) >= cos for j in kept):
            continue
        kept.append(int(k))
    return kept
