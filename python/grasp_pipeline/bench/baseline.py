"""The original design's Python perception pipeline, kept as the speed baseline.

method.md §1.1–1.3 in numpy (RANSAC on a subsample, counts on the whole cloud,
dominance then height), then Open3D's ``cluster_dbscan`` on the points above the
band and Open3D's oriented bounding box per cluster — what the published ROS 2
design ran per frame. Only the perception benchmark uses it; Open3D is the
optional ``bench`` extra (``pip install .[bench]``).
"""

from __future__ import annotations

import numpy as np

from ..perception.config import SceneFilterConfig


def _ransac_plane(pts: np.ndarray, cfg: SceneFilterConfig, rng: np.random.Generator):
    """One horizontal-constrained RANSAC plane with least-squares refinement."""
    cos_tilt = np.cos(np.radians(cfg.plane_max_tilt_deg))
    best_n, best_c, best_score = None, 0.0, -1
    for _ in range(cfg.plane_ransac_iters):
        p1, p2, p3 = pts[rng.choice(len(pts), 3, replace=False)]
        n = np.cross(p2 - p1, p3 - p1)
        norm = np.linalg.norm(n)
        if norm < 1e-12:
            continue
        n = n / norm
        if n[2] < 0:
            n = -n
        if n[2] < cos_tilt:
            continue
        c = -n @ p1
        score = int(np.count_nonzero(np.abs(pts @ n + c) < cfg.plane_dist_thresh))
        if score > best_score:
            best_n, best_c, best_score = n, c, score
    if best_n is None:
        return None
    inl = pts[np.abs(pts @ best_n + best_c) < cfg.plane_dist_thresh]
    centroid = inl.mean(axis=0)
    _, _, vt = np.linalg.svd(inl - centroid, full_matrices=False)
    n = vt[-1]
    if n[2] < 0:
        n = -n
    if n[2] < cos_tilt:
        return best_n, best_c, best_score
    return n, -n @ centroid, best_score


def baseline_frame(points: np.ndarray, cfg: SceneFilterConfig, seed: int = 0) -> dict:
    """Run the baseline on one frame; returns the table plane and the OBBs."""
    import open3d as o3d  # optional dependency: the bench extra

    rng = np.random.default_rng(seed)
    pts = points[np.isfinite(points).all(axis=1)].astype(np.float64)
    remaining = pts
    planes = []
    for _ in range(cfg.plane_max_count):
        if len(remaining) < 3:
            break
        k = min(cfg.plane_fit_max_points, len(remaining))
        sub = remaining[rng.choice(len(remaining), k, replace=False)]
        fit = _ransac_plane(sub, cfg, rng)
        if fit is None or fit[2] < cfg.plane_min_inlier_ratio * k:
            break
        n, c, _ = fit
        count = int(np.count_nonzero(np.abs(pts @ n + c) < cfg.plane_dist_thresh))
        planes.append((n, c, count))
        remaining = remaining[np.abs(remaining @ n + c) >= cfg.plane_dist_thresh]
    if not planes:
        return {"plane": None, "boxes": []}
    max_count = max(p[2] for p in planes)
    qualified = [p for p in planes if p[2] >= cfg.plane_dominance * max_count]
    n, c, _ = max(qualified, key=lambda p: -p[1] / p[0][2])
    above = pts[pts @ n + c > cfg.band]
    pcd = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(above))
    labels = np.asarray(pcd.cluster_dbscan(eps=cfg.cluster_eps, min_points=cfg.cluster_min_points))
    boxes = []
    for lab in range(labels.max() + 1 if len(labels) else 0):
        cl = above[labels == lab]
        extent = np.linalg.norm(cl.max(axis=0) - cl.min(axis=0))
        if extent < cfg.cluster_min_extent or (0 < cfg.cluster_max_extent < extent):
            continue
        obb = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(cl)).get_oriented_bounding_box()
        boxes.append((np.asarray(obb.center), np.asarray(obb.extent)))
    return {"plane": (n, c), "boxes": boxes}
