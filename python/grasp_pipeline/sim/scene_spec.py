"""Plain descriptions of a scene: which objects stand where (no MuJoCo in here).

Sizes are full extents in metres. Object frames: centre of the object, z up, yaw about z.
A cylinder's ``size_m`` is ``(diameter, diameter, height)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from .exceptions import SceneError

ObjectKind = Literal["cube", "cuboid", "cylinder", "mesh"]
#: Primitive kinds of the random (sparse) scenes.
OBJECT_KINDS: tuple[str, ...] = ("cube", "cuboid", "cylinder")
#: Every kind a scene may hold (``mesh``: an ObjectModel from grasp_pipeline.objects).
ALL_KINDS: tuple[str, ...] = OBJECT_KINDS + ("mesh",)


@dataclass(frozen=True)
class ObjectSpec:
    """One graspable object resting upright on the table.

    Attributes:
        name: unique name (also the MuJoCo body name, prefixed ``obj_``).
        kind: ``"cube"``, ``"cuboid"``, ``"cylinder"`` or ``"mesh"``.
        size_m: full extents (x, y, z) in the object frame; cylinders (d, d, h); a mesh's
            bounding box.
        position_m: centre of the object (of its bounding box) in world [m].
        yaw_rad: rotation about world z (when ``quat_wxyz`` is None).
        mesh: for ``kind="mesh"``: the :class:`~grasp_pipeline.objects.model.ObjectModel`
            (already scaled).
        quat_wxyz: a full 3-D orientation (e.g. a pile's random one) instead of ``yaw_rad``.
        category: what a user calls it ("mug"); defaults to the kind.
        rgba: colour.
        camera_visible: False makes the object invisible to the cameras (like glass) but
            still solid: a fault-injection obstacle perception cannot know about.
        fixed: True welds the object to the world (no free joint), e.g. such an obstacle.
    """

    name: str
    kind: str
    size_m: tuple[float, float, float]
    position_m: tuple[float, float, float]
    yaw_rad: float = 0.0
    rgba: tuple[float, float, float, float] = (0.6, 0.6, 0.6, 1.0)
    camera_visible: bool = True
    fixed: bool = False
    mesh: object = None
    quat_wxyz: tuple[float, float, float, float] | None = None
    category: str = ""

    def __post_init__(self) -> None:
        if self.kind not in ALL_KINDS:
            raise SceneError(f"object {self.name!r}: kind must be one of {ALL_KINDS}, got {self.kind!r}")
        if (self.kind == "mesh") != (self.mesh is not None):
            raise SceneError(f"object {self.name!r}: a mesh object needs its ObjectModel (and only it)")
        if len(self.size_m) != 3 or min(self.size_m) <= 0:
            raise SceneError(f"object {self.name!r}: size_m must be 3 positive extents, got {self.size_m}")
        if self.kind == "cylinder" and not math.isclose(self.size_m[0], self.size_m[1]):
            raise SceneError(f"cylinder {self.name!r}: size_m must be (d, d, h), got {self.size_m}")
        if self.kind == "cube" and not (math.isclose(self.size_m[0], self.size_m[1])
                                        and math.isclose(self.size_m[0], self.size_m[2])):
            raise SceneError(f"cube {self.name!r}: all three extents must be equal, got {self.size_m}")

    @property
    def height_m(self) -> float:
        return float(self.size_m[2])

    @property
    def footprint_radius_m(self) -> float:
        """Radius of the circle around the centre that contains the footprint."""
        if self.kind == "cylinder":
            return 0.5 * self.size_m[0]
        return 0.5 * math.hypot(self.size_m[0], self.size_m[1])

    def pose(self) -> np.ndarray:
        """4x4 world pose of the object frame (centre; yaw about z or ``quat_wxyz``)."""
        T = np.eye(4)
        if self.quat_wxyz is not None:
            w, x, y, z = (float(v) for v in self.quat_wxyz)
            n = math.sqrt(w * w + x * x + y * y + z * z)
            w, x, y, z = w / n, x / n, y / n, z / n
            T[:3, :3] = [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                         [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                         [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]
        else:
            c, s = math.cos(self.yaw_rad), math.sin(self.yaw_rad)
            T[:2, :2] = [[c, -s], [s, c]]
        T[:3, 3] = self.position_m
        return T


@dataclass(frozen=True)
class SceneSpec:
    """A scene: the fixed set-up (table, wall, tray — in ``sim/scene_base.xml``) plus objects.

    Attributes:
        name: label for logs and reports.
        objects: the graspable objects.
        table_top_z_m: height of the table top (must match ``scene_base.xml``).
        start_q: the arm's start ("ready") joints.
        seed: generator seed, or None for hand-made scenes.
    """

    name: str
    objects: tuple[ObjectSpec, ...]
    table_top_z_m: float
    start_q: tuple[float, ...]
    seed: int | None = None
    notes: tuple[str, ...] = field(default_factory=tuple)

    def __post_init__(self) -> None:
        names = [o.name for o in self.objects]
        if len(set(names)) != len(names):
            raise SceneError(f"scene {self.name!r}: object names must be unique, got {names}")
        if len(self.start_q) != 7:
            raise SceneError(f"scene {self.name!r}: start_q must have 7 joints")
