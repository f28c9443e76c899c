"""Ground truth about the scene's objects — **for evaluation code only**.

Perception, planning and execution must never import this module: they work from depth frames
and the robot's own state, as on a real robot. Scoring code (reports, benchmarks, tests) reads
here what really stands where.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .object_geoms import object_body_name
from .world import SimWorld


@dataclass(frozen=True)
class ObjectTruth:
    """The true state of one object at the moment of the query.

    Attributes:
        name, kind: as in the scene's :class:`~.scene_spec.ObjectSpec`.
        size_m: full extents (x, y, z) in the object frame; cylinders (d, d, h).
        T_world_object: 4x4 pose of the object's centre frame now.
        initial_T_world_object: 4x4 pose the scene placed it at.
    """

    name: str
    kind: str
    size_m: tuple[float, float, float]
    T_world_object: np.ndarray
    initial_T_world_object: np.ndarray

    @property
    def position_m(self) -> np.ndarray:
        return self.T_world_object[:3, 3].copy()

    @property
    def top_z_m(self) -> float:
        """Height of the highest point, assuming the object stands upright."""
        return float(self.T_world_object[2, 3] + 0.5 * self.size_m[2])


def object_truths(world: SimWorld) -> list[ObjectTruth]:
    """Every object's true pose and size, in the scene's order."""
    out = []
    for obj in world.scene.objects:
        bid = world.model.body(object_body_name(obj)).id
        T = np.eye(4)
        T[:3, :3] = world.data.xmat[bid].reshape(3, 3)
        T[:3, 3] = world.data.xpos[bid]
        out.append(ObjectTruth(obj.name, obj.kind, tuple(obj.size_m), T, obj.pose()))
    return out


def object_truth(world: SimWorld, name: str) -> ObjectTruth:
    """The truth about one object, by scene name (e.g. ``"blue_cube"``)."""
    for t in object_truths(world):
        if t.name == name:
            return t
    raise KeyError(f"no object {name!r} in scene {world.scene.name!r}; "
                   f"known: {[o.name for o in world.scene.objects]}")
