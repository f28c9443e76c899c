"""What a Rerun recording draws, as plain arrays (no Rerun here, so it is tested on its own).

* :func:`split_cloud` — one perceived frame's object points (red) and environment points
  (blue), each thinned to a limit with a fixed stride (deterministic), as the snapshots do;
* :class:`BoxBatch` / :func:`track_boxes` — each track's oriented box, with its label
  (``#tid nadir``) and a colour by view quality;
* :func:`gripper_strips` — a grasp drawn as an open parallel gripper (two fingers along the
  approach, joined by the palm), :func:`approach_arrows` — candidates as arrows;
* :func:`depth_mm` — a float depth image [m] as uint16 millimetres (0 = no return);
* :class:`TcpKinematics` — TCP positions of joint states (a planned trajectory), by the
  robot model's forward kinematics.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np
from scipy.spatial.transform import Rotation

OBJECT_RGB = (255, 0, 0)         # red, as the snapshots
ENVIRONMENT_RGB = (26, 77, 255)  # blue, as the snapshots
NADIR_RGB = (0, 217, 0)          # green: a box seen from above
OBLIQUE_RGB = (255, 200, 0)      # amber: a box seen only obliquely
CANDIDATE_RGB = (255, 140, 0)    # orange: candidate grasps
CHOSEN_RGB = (0, 255, 255)       # cyan: the grasp whose motions were planned
PLANNED_RGB = (255, 0, 255)      # magenta: the planned TCP path
EXECUTED_RGB = (255, 255, 255)   # white: the executed TCP path

#: Finger length drawn for a grasp, and the arrow length of a candidate [m] (drawing only).
FINGER_DRAW_M = 0.05
ARROW_DRAW_M = 0.08
#: Largest depth stored in a uint16 millimetre image [m].
MAX_DEPTH_MM = np.iinfo(np.uint16).max


def stride_subsample(points: np.ndarray, limit: int) -> np.ndarray:
    """At most ``limit`` rows of ``points`` with a fixed stride (all of them when fewer)."""
    if len(points) <= limit:
        return points
    if limit <= 0:
        return points[:0]
    idx = np.linspace(0, len(points) - 1, limit).astype(np.int64)
    return points[idx]


def split_cloud(result, max_object_points: int, max_environment_points: int
                ) -> tuple[np.ndarray, np.ndarray]:
    """(object points, environment points) of a ``perception.FrameResult``, finite, float32,
    each thinned to its limit."""
    obj, _ = result.object_points()
    env = result.environment_points()
    out = []
    for pts, limit in ((obj, max_object_points), (env, max_environment_points)):
        p = np.asarray(pts, dtype=np.float32).reshape(-1, 3)
        p = p[np.isfinite(p).all(axis=1)]
        out.append(stride_subsample(p, limit))
    return out[0], out[1]


@dataclass(frozen=True)
class BoxBatch:
    """Oriented boxes as Rerun takes them: centres, half sizes, quaternions (x, y, z, w)."""

    centers: np.ndarray
    half_sizes: np.ndarray
    quaternions_xyzw: np.ndarray
    labels: list
    colors: np.ndarray

    def __len__(self) -> int:
        return len(self.centers)


def quality_name(quality) -> str:
    """``nadir`` / ``oblique`` of a ``_core.ViewQuality`` (or anything with a ``name``)."""
    return str(getattr(quality, "name", quality)).lower()


def track_boxes(tracks: Sequence) -> BoxBatch:
    """The smoothed box of each track (``_core.Track``), labelled ``#tid quality`` with its
    sizes in mm; green when seen from above (NADIR), amber when only obliquely."""
    centers, halves, quats, labels, colors = [], [], [], [], []
    for t in tracks:
        e = t.smoothed
        R = np.asarray(e.R_box, dtype=float)
        if np.linalg.det(R) < 0:  # a reflection: flip one axis (a box is symmetric)
            R = R * np.array([1.0, 1.0, -1.0])
        ext = np.asarray(e.extents, dtype=float)
        q = quality_name(t.quality)
        centers.append(np.asarray(e.center, dtype=float))
        halves.append(0.5 * ext)
        quats.append(Rotation.from_matrix(R).as_quat())
        labels.append(f"#{int(t.tid)} {q} {ext[0] * 1e3:.0f}x{ext[1] * 1e3:.0f}x{ext[2] * 1e3:.0f} mm")
        colors.append(NADIR_RGB if q == "nadir" else OBLIQUE_RGB)
    shape3 = (len(centers), 3)
    return BoxBatch(np.reshape(centers, shape3), np.reshape(halves, shape3),
                    np.reshape(quats, (len(quats), 4)), labels,
                    np.reshape(np.asarray(colors, dtype=np.uint8), shape3))


def grasp_frame(grasp) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """(contact point, unit approach, unit closing axis, width [m]) of a ``BestGrasp``."""
    R = np.asarray(grasp.R, dtype=float)
    a = R[:, 0] / np.linalg.norm(R[:, 0])
    c = R[:, 2] - np.dot(R[:, 2], a) * a
    return np.asarray(grasp.position, dtype=float), a, c / np.linalg.norm(c), float(grasp.width_m)


def gripper_strips(grasp, finger_m: float = FINGER_DRAW_M) -> list[np.ndarray]:
    """An open parallel gripper at a grasp: one (4, 3) strip — finger tip, finger base, other
    finger base, other tip — fingers ``width_m`` apart across the closing axis, tips at the
    contact point's depth."""
    p, a, c, w = grasp_frame(grasp)
    half = 0.5 * w * c
    tip1, tip2 = p + half, p - half
    return [np.stack([tip1, tip1 - finger_m * a, tip2 - finger_m * a, tip2])]


def approach_arrows(grasps: Sequence, length_m: float = ARROW_DRAW_M) -> tuple[np.ndarray, np.ndarray]:
    """(origins, vectors) of arrows ending at each grasp's contact point along its approach."""
    origins, vectors = [], []
    for g in grasps:
        p, a, _, _ = grasp_frame(g)
        origins.append(p - length_m * a)
        vectors.append(length_m * a)
    return np.reshape(origins, (len(origins), 3)), np.reshape(vectors, (len(vectors), 3))


def depth_mm(depth: np.ndarray) -> np.ndarray:
    """(H, W) float depth [m] with NaN holes → uint16 millimetres, 0 where there is no return
    (Rerun's "no depth"), clipped at 65.535 m."""
    d = np.asarray(depth, dtype=np.float64)
    mm = np.where(np.isfinite(d) & (d > 0), np.rint(d * 1e3), 0.0)
    return np.clip(mm, 0, MAX_DEPTH_MM).astype(np.uint16)


def sample_rows(n: int, limit: int) -> np.ndarray:
    """Indices of at most ``limit`` rows of ``n``, evenly spread, first and last included."""
    if n <= limit:
        return np.arange(n)
    return np.unique(np.linspace(0, n - 1, limit).round().astype(np.int64))


class TcpKinematics:
    """World TCP positions of arm joint states, from the robot model (robot base at the world
    origin, as the planner assumes)."""

    def __init__(self) -> None:
        from ..motion.kinematics import ChainKinematics
        from ..robot import description as rm

        model = rm.load_robot_model()
        self._fk = ChainKinematics(model, rm.arm_qpos_indices(model))
        self._flange = int(model.body(rm.FLANGE_BODY).id)
        self._flange_T_tcp = rm.flange_T_tcp(model)

    def positions(self, Q: np.ndarray) -> np.ndarray:
        """(N, 3) TCP positions [m] of joint states ``Q`` (N, 7)."""
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        R, p = self._fk.body_poses(Q, bodies_needed=self._flange + 1)
        Rf, pf = R[:, self._flange], p[:, self._flange]
        return pf + Rf @ self._flange_T_tcp[:3, 3]
