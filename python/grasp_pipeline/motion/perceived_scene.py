"""The scene as perception delivers it to the motion layer, and the camera-above pose.

:class:`PerceivedScene` is what planning may use: environment points (table, floor, walls —
everything that is not an accepted object) and one oriented box per object. It never holds
simulator ground truth.

:func:`perceive_scene` is the single place where a world's camera frame becomes a
``PerceivedScene``. **DEVELOPMENT STAND-IN, to be replaced by the C++ perception core**
(``grasp_pipeline._core`` scene filter + OBB estimate, wired by the lead): until then it uses
the camera frame only — a z-histogram table height, points more than 1 cm above it are
object candidates, grouped by a 1.5 cm radius connected-components clustering, each cluster
boxed by a minimum-width yaw scan (like SPEC 2.2) from the table up to its highest point;
every other valid point is environment. It reads nothing but the frame (never ground truth).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .occupancy import OrientedBox

# Development stand-in parameters (the real ones live in the perception core's config).
_DEV_BAND_M = 0.01
_DEV_HIST_BIN_M = 0.005
_DEV_CLUSTER_EPS_M = 0.015
_DEV_CLUSTER_MIN_POINTS = 20
_DEV_CLUSTER_MIN_EXTENT_M = 0.01
_DEV_CLUSTER_MAX_EXTENT_M = 0.30
_DEV_YAW_STEPS = 90
_DEV_MAX_CLUSTER_POINTS = 3000


@dataclass(frozen=True)
class PerceivedScene:
    """Perceived obstacles: ``environment_points`` (N, 3) world, ``object_boxes`` (oriented
    boxes of the objects, index = object id within this scene), ``table_height_m`` (or None),
    ``capture_q`` (arm joints at capture, for filtering the robot's own points; or None)."""

    environment_points: np.ndarray
    object_boxes: list[OrientedBox] = field(default_factory=list)
    table_height_m: float | None = None
    capture_q: np.ndarray | None = None
    T_world_camera: np.ndarray | None = None


def _table_height(z: np.ndarray) -> float:
    lo, hi = float(np.min(z)), float(np.max(z))
    bins = max(1, int(np.ceil((hi - lo) / _DEV_HIST_BIN_M)))
    hist, edges = np.histogram(z, bins=bins, range=(lo, lo + bins * _DEV_HIST_BIN_M))
    k = int(np.argmax(hist))
    sel = z[(z >= edges[k]) & (z < edges[k + 1])]
    return float(np.median(sel))


def _clusters(points: np.ndarray) -> list[np.ndarray]:
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    if len(points) == 0:
        return []
    pairs = cKDTree(points).query_pairs(_DEV_CLUSTER_EPS_M, output_type="ndarray")
    n = len(points)
    g = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, labels = connected_components(g, directed=False)
    out = []
    for lab in np.unique(labels):
        idx = np.nonzero(labels == lab)[0]
        if len(idx) < _DEV_CLUSTER_MIN_POINTS:
            continue
        ext = float(np.linalg.norm(points[idx].max(0) - points[idx].min(0)))
        if _DEV_CLUSTER_MIN_EXTENT_M <= ext <= _DEV_CLUSTER_MAX_EXTENT_M:
            out.append(points[idx])
    return out


def _box_of(points: np.ndarray, table_z: float) -> OrientedBox:
    xy = points[:, :2]
    best = None
    for th in np.linspace(0.0, np.pi / 2, _DEV_YAW_STEPS, endpoint=False):
        c, s = np.cos(th), np.sin(th)
        a = xy @ np.array([c, s])
        b = xy @ np.array([-s, c])
        area = (a.max() - a.min()) * (b.max() - b.min())
        if best is None or area < best[0]:
            best = (area, th, a, b)
    _, th, a, b = best
    c, s = np.cos(th), np.sin(th)
    R = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    ca, cb = 0.5 * (a.max() + a.min()), 0.5 * (b.max() + b.min())
    top = float(points[:, 2].max())
    centre = np.array([ca * c - cb * s, ca * s + cb * c, 0.5 * (top + table_z)])
    return OrientedBox(centre, R, np.array([a.max() - a.min(), b.max() - b.min(), top - table_z]))


def split_points_dev(points_world: np.ndarray) -> tuple[np.ndarray, list[OrientedBox], float]:
    """DEVELOPMENT STAND-IN: (environment points, object boxes, table height) from one cloud."""
    pts = np.asarray(points_world, dtype=float)
    pts = pts[np.all(np.isfinite(pts), axis=1)]
    if len(pts) == 0:
        return pts.reshape(0, 3), [], float("nan")
    table_z = _table_height(pts[:, 2])
    above = pts[:, 2] > table_z + _DEV_BAND_M
    cand = pts[above]
    # object candidates are sub-sampled for clustering speed; every point keeps its role
    rng = np.random.default_rng(0)
    sample = cand if len(cand) <= 20 * _DEV_MAX_CLUSTER_POINTS else \
        cand[rng.choice(len(cand), 20 * _DEV_MAX_CLUSTER_POINTS, replace=False)]
    clusters = _clusters(sample)
    boxes = [_box_of(c, table_z) for c in clusters]
    if boxes:
        inside = np.zeros(len(cand), dtype=bool)
        for b in boxes:
            inside |= b.inflated(0.005).contains(cand)
        env = np.vstack([pts[~above], cand[~inside]])
    else:
        env = pts
    return env, boxes, table_z


def perceive_scene(world) -> PerceivedScene:
    """The scene as perceived from the world's current camera view.

    DEVELOPMENT STAND-IN — replace the body with the perception core (scene filter → object
    estimates) when ``grasp_pipeline._core`` is wired; keep the signature.
    """
    frame = world.capture()
    env, boxes, table_z = split_points_dev(frame.valid_points())
    return PerceivedScene(environment_points=env, object_boxes=boxes,
                          table_height_m=None if not np.isfinite(table_z) else table_z,
                          capture_q=np.asarray(world.q, dtype=float).copy(),
                          T_world_camera=frame.T_world_camera.copy())


def camera_above_flange_pose(object_center: np.ndarray, plane_normal: np.ndarray,
                             ready_T_world_camera: np.ndarray, flange_T_camera: np.ndarray,
                             plane_u: np.ndarray | None = None) -> np.ndarray:
    """SPEC 3 camera-above pose, returned as the flange target (4x4).

    Camera z = -n; camera x = the ready pose's camera x projected into the plane (fallback
    ``plane_u`` — default a unit vector ⟂ n — when that projection is shorter than 1e-6);
    y = z × x; camera position = the object's (x, y) at the ready camera's height. Flange:
    ``R_f = R_wc · R_lcᵀ``, ``p_f = p_c − R_f · t_lc``.
    """
    n = np.asarray(plane_normal, dtype=float)
    n = n / np.linalg.norm(n)
    z_c = -n
    x_ready = np.asarray(ready_T_world_camera, dtype=float)[:3, 0]
    x_c = x_ready - np.dot(x_ready, n) * n
    if np.linalg.norm(x_c) < 1e-6:
        if plane_u is None:
            a = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
            plane_u = a - np.dot(a, n) * n
        x_c = np.asarray(plane_u, dtype=float)
    x_c = x_c / np.linalg.norm(x_c)
    y_c = np.cross(z_c, x_c)
    T_wc = np.eye(4)
    T_wc[:3, :3] = np.column_stack([x_c, y_c, z_c])
    T_wc[:3, 3] = [object_center[0], object_center[1], ready_T_world_camera[2, 3]]
    R_lc, t_lc = flange_T_camera[:3, :3], flange_T_camera[:3, 3]
    T_f = np.eye(4)
    T_f[:3, :3] = T_wc[:3, :3] @ R_lc.T
    T_f[:3, 3] = T_wc[:3, 3] - T_f[:3, :3] @ t_lc
    return T_f
