"""Small pose helpers (4x4 homogeneous transforms) and input validation."""

from __future__ import annotations

import numpy as np

from .exceptions import InvalidPoseError

_ROTATION_TOL = 1e-6


def validate_pose(T: np.ndarray, what: str = "pose") -> np.ndarray:
    """Return ``T`` as a float (4, 4) array or raise InvalidPoseError naming the defect."""
    try:
        T = np.asarray(T, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InvalidPoseError(f"{what} is not a numeric 4x4 matrix: {exc}") from None
    if T.shape != (4, 4):
        raise InvalidPoseError(f"{what} must be a 4x4 homogeneous transform, got shape {T.shape}")
    if not np.all(np.isfinite(T)):
        raise InvalidPoseError(f"{what} contains NaN/Inf: {np.array2string(T, precision=4)}")
    R = T[:3, :3]
    ortho = np.abs(R.T @ R - np.eye(3)).max()
    if ortho > _ROTATION_TOL or np.linalg.det(R) < 0:
        raise InvalidPoseError(
            f"{what} rotation is not a proper rotation (|RᵀR - I| = {ortho:.2e}, det = {np.linalg.det(R):.4f})")
    if np.abs(T[3] - np.array([0.0, 0.0, 0.0, 1.0])).max() > _ROTATION_TOL:
        raise InvalidPoseError(f"{what} last row must be (0, 0, 0, 1), got {T[3]}")
    return T


def validate_joints(q: np.ndarray, what: str = "joint vector", n: int = 7) -> np.ndarray:
    try:
        q = np.asarray(q, dtype=float).reshape(-1)
    except (TypeError, ValueError) as exc:
        raise InvalidPoseError(f"{what} is not numeric: {exc}") from None
    if q.shape != (n,):
        raise InvalidPoseError(f"{what} must have {n} values, got {q.shape[0]}")
    if not np.all(np.isfinite(q)):
        raise InvalidPoseError(f"{what} contains NaN/Inf: {q}")
    return q


def pose_inverse(T: np.ndarray) -> np.ndarray:
    Ti = np.eye(4)
    Ti[:3, :3] = T[:3, :3].T
    Ti[:3, 3] = -T[:3, :3].T @ T[:3, 3]
    return Ti


def rotation_log(R: np.ndarray) -> np.ndarray:
    """Rotation vector (axis * angle) of one rotation matrix (robust near 0 and π)."""
    from scipy.spatial.transform import Rotation

    return Rotation.from_matrix(R).as_rotvec()


def rotation_angle(R: np.ndarray) -> float:
    """Angle of a rotation matrix [rad]: atan2(|vee(R - Rᵀ)|/2, (tr R - 1)/2), accurate for
    small angles (unlike arccos of the trace) and up to π."""
    s = 0.5 * np.sqrt((R[2, 1] - R[1, 2]) ** 2 + (R[0, 2] - R[2, 0]) ** 2 + (R[1, 0] - R[0, 1]) ** 2)
    c = 0.5 * (R[0, 0] + R[1, 1] + R[2, 2] - 1.0)
    return float(np.arctan2(s, c))


def pose_error(T_target: np.ndarray, T: np.ndarray) -> tuple[float, float]:
    """(position error [m], orientation error [rad]) between two poses."""
    return (float(np.linalg.norm(T_target[:3, 3] - T[:3, 3])),
            rotation_angle(T_target[:3, :3] @ T[:3, :3].T))
