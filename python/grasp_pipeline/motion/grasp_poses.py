"""TCP poses of a top-down grasp (method.md §3 / 7): the one place the closing sign is chosen.

Our TCP frame (``grasp_pipeline.robot.description``): z = approach (into the object),
y = closing axis, x = y × z. A parallel gripper's closing axis has no sign; of the two, the
one whose hand orientation is nearer a reference TCP orientation (e.g. the current one) is
chosen, which keeps joint 7 away from its limits.
"""

from __future__ import annotations

import numpy as np

from .poses import rotation_angle


def tcp_rotation(approach: np.ndarray, closing: np.ndarray,
                 reference_tcp: np.ndarray | None = None) -> np.ndarray:
    """TCP rotation (3x3) with z = ``approach`` and y = ±``closing`` (made orthogonal to the
    approach), the sign nearer ``reference_tcp`` (4x4 or 3x3; None: +closing)."""
    z = np.asarray(approach, dtype=float)
    z = z / np.linalg.norm(z)
    c = np.asarray(closing, dtype=float)
    c = c - np.dot(c, z) * z
    if np.linalg.norm(c) < 1e-9:
        raise ValueError("closing axis is parallel to the approach: degenerate grasp")
    c /= np.linalg.norm(c)
    best = None
    for sign in (1.0, -1.0):
        y = sign * c
        R = np.column_stack([np.cross(y, z), y, z])
        if reference_tcp is None:
            return R
        d = rotation_angle(R @ np.asarray(reference_tcp)[:3, :3].T)
        if best is None or d < best[0]:
            best = (d, R)
    return best[1]


def tcp_pose_from_grasp(grasp, reference_tcp: np.ndarray | None = None) -> np.ndarray:
    """TCP pose (4x4) of a grasp (position = contact point, rotation column 0 = approach into
    the object, column 2 = closing axis): the grasp's own ``tcp_R`` when its source chose the
    hand orientation, else the closing sign nearer ``reference_tcp``."""
    R = np.asarray(grasp.R, dtype=float)
    T = np.eye(4)
    chosen = getattr(grasp, "tcp_R", None)
    T[:3, :3] = tcp_rotation(R[:, 0], R[:, 2], reference_tcp) if chosen is None else chosen
    T[:3, 3] = np.asarray(grasp.position, dtype=float)
    return T


def offset_along(T: np.ndarray, direction: np.ndarray, distance_m: float) -> np.ndarray:
    """``T`` translated by ``distance_m`` along the world ``direction``."""
    out = T.copy()
    d = np.asarray(direction, dtype=float)
    out[:3, 3] = T[:3, 3] + distance_m * d / np.linalg.norm(d)
    return out
