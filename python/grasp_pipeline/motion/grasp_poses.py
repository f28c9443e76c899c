"""TCP poses of a top-down grasp motion from an object box (SPEC 3 / 7).

SPEC 3 builds the grasp rotation from the plane normal ``n`` and the closing axis
(``R_box[:, 0]``). In our TCP frame (``grasp_pipeline.sim.robot_model``): z = approach =
``-n`` (into the object), y = closing axis, x = y × z; position = the box centre.
The closing axis' sign is free; the sign whose hand orientation is nearer the reference
TCP orientation (e.g. the current one) is chosen, which keeps joint 7 away from its limits.
"""

from __future__ import annotations

import numpy as np

from .occupancy import OrientedBox
from .poses import rotation_angle


def top_down_grasp_tcp(box: OrientedBox, plane_normal: np.ndarray = np.array([0.0, 0.0, 1.0]),
                       reference_tcp: np.ndarray | None = None, closing_axis: int = 0) -> np.ndarray:
    """TCP pose (4x4) for a top-down grasp of ``box`` closing along its axis ``closing_axis``."""
    n = np.asarray(plane_normal, dtype=float)
    n = n / np.linalg.norm(n)
    closing = box.R[:, closing_axis]
    closing = closing - np.dot(closing, n) * n
    if np.linalg.norm(closing) < 1e-9:
        raise ValueError("closing axis is parallel to the plane normal: degenerate footprint")
    closing /= np.linalg.norm(closing)
    z = -n
    best = None
    for sign in (1.0, -1.0):
        y = sign * closing
        x = np.cross(y, z)
        R = np.column_stack([x, y, z])
        d = 0.0 if reference_tcp is None else rotation_angle(R @ reference_tcp[:3, :3].T)
        if best is None or d < best[0]:
            best = (d, R)
    T = np.eye(4)
    T[:3, :3] = best[1]
    T[:3, 3] = box.center
    return T


def offset_along(T: np.ndarray, direction: np.ndarray, distance_m: float) -> np.ndarray:
    """``T`` translated by ``distance_m`` along the world ``direction``."""
    out = T.copy()
    d = np.asarray(direction, dtype=float)
    out[:3, 3] = T[:3, 3] + distance_m * d / np.linalg.norm(d)
    return out
