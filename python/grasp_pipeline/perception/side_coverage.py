"""How well the sides of an object are known: the unknown part of the shell around its box.

The *shell* is the space a hand needs beside the object: the voxels within
``side_view_shell_m`` of the box's four vertical faces (outside the box), from
``side_view_table_clearance_m`` above the table to the box's top. Each shell voxel belongs to
the face it lies farthest out from (the corners are split along the diagonals). Shell voxels
inside a neighbour's box do not count (under a lying bottle nothing is ever seen, and no hand
goes there). A face whose shell is mostly UNKNOWN was never seen, nor the space beside it: a
grasp from that side would reach into the unknown.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from .scene_volume import UNKNOWN, SceneVolume

#: The box faces, in the box frame: +x, +y, -x, -y.
FACES = ("+x", "+y", "-x", "-y")


@dataclass(frozen=True)
class SideCoverage:
    """Per face (:data:`FACES`): shell voxels and the fraction of them UNKNOWN;
    ``unknown_points``: the centres of the unknown shell voxels (M, 3) [m, world]."""

    voxels: tuple[int, ...]
    unknown_fraction: tuple[float, ...]
    unknown_points: np.ndarray

    @property
    def worst(self) -> float:
        """The largest unknown fraction of a face (0 when the shell is empty)."""
        return max(self.unknown_fraction, default=0.0)

    @property
    def overall(self) -> float:
        """The unknown fraction of the whole shell."""
        total = sum(self.voxels)
        return len(self.unknown_points) / total if total else 0.0

    def summary(self) -> dict:
        return {face: round(f, 3) for face, f in zip(FACES, self.unknown_fraction)}


def shell_mask(local: np.ndarray, half_xy: np.ndarray, shell_m: float) -> tuple[np.ndarray, np.ndarray]:
    """(in the shell, face index 0..3) for points in the box frame (``local`` (N, 3))."""
    out = np.abs(local[:, :2]) - half_xy  # > 0: outside the box along that axis
    far = out.max(axis=1)
    inside_shell = (far > 0) & (out[:, 0] <= shell_m) & (out[:, 1] <= shell_m)
    along_x = out[:, 0] >= out[:, 1]
    face = np.where(along_x, np.where(local[:, 0] >= 0, 0, 2), np.where(local[:, 1] >= 0, 1, 3))
    return inside_shell, face


def inside_any(points: np.ndarray, boxes: Sequence[tuple]) -> np.ndarray:
    """(N,) bool: points inside any of the boxes (``(center, R, extents)``)."""
    out = np.zeros(len(points), dtype=bool)
    for c, R, ext in boxes:
        local = (points - np.asarray(c, float)) @ np.asarray(R, float)
        out |= np.all(np.abs(local) <= 0.5 * np.asarray(ext, float), axis=1)
    return out


def side_coverage(volume: SceneVolume, center, R, extents, plane, shell_m: float,
                  table_clearance_m: float, neighbours: Sequence[tuple] = (),
                  interior: bool = False) -> SideCoverage:
    """The shell of the box (``center``, rotation ``R`` whose columns are the box axes,
    full ``extents``; z = up) above ``plane`` (``n``, ``c``) in ``volume``, less the
    ``neighbours``' boxes (``(center, R, extents)`` each); ``interior``: the box's own
    volume too, counted with the face it is nearest (under a leaning object, say)."""
    c = np.asarray(center, float)
    Rb = np.asarray(R, float)
    half = 0.5 * np.asarray(extents, float)
    grown = half + np.array([shell_m, shell_m, 0.0])
    reach = np.abs(Rb) @ grown  # half-size of the grown box's world AABB
    centres, states = volume.states_in_box(c - reach, c + reach)
    if len(centres) == 0:
        return SideCoverage((0,) * 4, (0.0,) * 4, np.zeros((0, 3)))
    local = (centres - c) @ Rb
    n, off = np.asarray(plane.n, float), float(plane.c)
    above = centres @ n + off >= table_clearance_m
    in_shell, face = shell_mask(local, half[:2], shell_m)
    if interior:
        in_shell |= np.all(np.abs(local[:, :2]) <= half[:2], axis=1)
    keep = in_shell & above & (local[:, 2] <= half[2])
    if len(neighbours):
        keep[keep] = ~inside_any(centres[keep], neighbours)
    unknown = keep & (states == UNKNOWN)
    voxels = tuple(int(np.count_nonzero(keep & (face == k))) for k in range(4))
    fractions = tuple(float(np.count_nonzero(unknown & (face == k))) / v if v else 0.0
                      for k, v in enumerate(voxels))
    return SideCoverage(voxels, fractions, centres[unknown])
