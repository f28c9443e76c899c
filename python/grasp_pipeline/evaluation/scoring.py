"""Ground-truth scoring of a run — **evaluation code only** (reports, benchmarks, tests).

Reads the simulator's ground truth; the perception loop, the scan, selection and the grasp
action never import it.
"""

from __future__ import annotations

import math
from typing import Optional

import numpy as np

from ..sim.ground_truth import object_truths

#: yaw symmetry of each object kind [deg] (None: round, yaw undefined)
YAW_SYMMETRY_DEG = {"cube": 90.0, "cuboid": 180.0, "cylinder": None}
#: a footprint whose two sides differ by no more than perception's closing-direction
#: tolerance (``obb.width_tol_m``) has two equivalent closing directions (method.md §2.3)
SQUARE_SYMMETRY_DEG = 90.0


def _closing_axis(truth, est_closing_xy: np.ndarray, square_tol_m: float) -> tuple[int, float]:
    """The true box axis (0 = x, 1 = y) the estimate's closing direction stands for, and the
    yaw symmetry [deg] the comparison uses (None: round)."""
    sym = YAW_SYMMETRY_DEG.get(truth.kind)
    sx, sy = truth.size_m[0], truth.size_m[1]
    if sym is not None and abs(sx - sy) <= square_tol_m:
        sym = SQUARE_SYMMETRY_DEG
    if sym is None or sym == SQUARE_SYMMETRY_DEG:
        # either side is a valid closing direction: the one nearest the estimate
        R = truth.T_world_object[:3, :3]
        c = np.asarray(est_closing_xy, dtype=float)
        k = 0 if abs(float(R[:2, 0] @ c)) >= abs(float(R[:2, 1] @ c)) else 1
        return k, sym
    return (0 if sx <= sy else 1), sym  # the narrow side is the closing direction


def _yaw_error_deg(est_closing_xy: np.ndarray, truth, square_tol_m: float) -> Optional[float]:
    k, sym = _closing_axis(truth, est_closing_xy, square_tol_m)
    if sym is None:
        return None
    axis = truth.T_world_object[:3, k]
    a_true = math.degrees(math.atan2(axis[1], axis[0]))
    a_est = math.degrees(math.atan2(est_closing_xy[1], est_closing_xy[0]))
    d = (a_est - a_true) % sym
    return float(min(d, sym - d))


def score_estimates(world, tracks, square_tol_m: float) -> list[dict]:
    """Per true object: the nearest track's errors (centre, width, height, yaw mod symmetry).

    ``square_tol_m`` is perception's closing-direction tolerance (``obb.width_tol_m``): a
    cuboid whose sides differ by less has two equivalent closing directions, like a cube, so
    its yaw is compared modulo 90° and its width against the side the estimate closes on.
    """
    out = []
    truths = object_truths(world)
    for t in truths:
        row = {"object": t.name, "kind": t.kind, "true_size_m": list(t.size_m), "tid": None}
        if tracks:
            d = [np.linalg.norm(np.asarray(tr.smoothed.center)[:2] - t.position_m[:2]) for tr in tracks]
            k = int(np.argmin(d))
            if d[k] < 0.5 * min(t.size_m[0], t.size_m[1]) + 0.02:
                e = tracks[k].smoothed
                closing_xy = np.asarray(e.R_box)[:2, 0]
                axis, _ = _closing_axis(t, closing_xy, square_tol_m)
                true_w = t.size_m[axis]
                row.update({
                    "tid": int(tracks[k].tid),
                    "quality": tracks[k].quality.name,
                    "center_err_mm": float(np.linalg.norm(np.asarray(e.center) - t.position_m) * 1e3),
                    "width_err_mm": float(abs(e.width_m - true_w) * 1e3),
                    "height_err_mm": float(abs(e.height_m - t.size_m[2]) * 1e3),
                    "yaw_err_deg": _yaw_error_deg(closing_xy, t, square_tol_m),
                    "pca_tilt_deg": float(e.pca_tilt_deg),
                })
        out.append(row)
    return out
