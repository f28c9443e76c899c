"""Whether an episode's target object rests in the tray — the environment's success rule.

Ground truth, evaluation code only (the policy never reads it): the target *rests in the tray*
when its centre lies over the tray floor near its height (as the pick evaluation scores a
placed object, :func:`~.pick_evaluator.tray_holds`), it moves slower than ``rest_speed_mps``
and turns slower than ``rest_angular_speed_rad_s``, and no part of the robot touches it (it
was let go). :meth:`TargetOutcome.where` says where the target is otherwise (an episode's
failure reason).
"""

from __future__ import annotations

import mujoco
import numpy as np

from ..sim.ground_truth import object_body_id
from ..sim.object_geoms import OBJECT_PREFIX, geom_object
from .pick_evaluator import tray_holds

#: Below the table top by more than this [m]: the target fell off the table.
FALLEN_BELOW_M = 0.05
#: Above its start by more than this [m]: the target is up in the air (held or on its way).
LIFTED_M = 0.02


class TargetOutcome:
    """The target ``name`` of ``world`` (a :class:`~grasp_pipeline.sim.world.SimWorld`)."""

    def __init__(self, world, name: str, rest_speed_mps: float, rest_angular_speed_rad_s: float) -> None:
        self.world, self.name = world, name
        self.body = object_body_id(world, name)
        if self.body is None:
            raise KeyError(f"no object {name!r} in scene {world.scene.name!r}")
        self.cell = world.work_cell
        self.rest_speed_mps, self.rest_angular_speed_rad_s = rest_speed_mps, rest_angular_speed_rad_s
        self.geom = f"{OBJECT_PREFIX}{name}"
        self.z0 = float(world.data.xpos[self.body][2])
        self.table_top_z = float(self.cell.table.center[2] + 0.5 * self.cell.table.extents[2])

    def position_m(self) -> np.ndarray:
        return self.world.data.xpos[self.body].copy()

    def speeds(self) -> tuple[float, float]:
        """(linear [m/s], angular [rad/s]) speed of the target now."""
        v = np.zeros(6)
        mujoco.mj_objectVelocity(self.world.model, self.world.data, mujoco.mjtObj.mjOBJ_BODY,
                                 self.body, v, 0)
        return float(np.linalg.norm(v[3:])), float(np.linalg.norm(v[:3]))

    def touched_by_robot(self) -> bool:
        return any(geom_object(other) == self.geom for _, other in self.world.robot_contacts())

    def in_tray(self) -> bool:
        return tray_holds(self.cell, self.position_m())

    def rests_in_tray(self) -> bool:
        """The success rule (see the module doc)."""
        if not self.in_tray():
            return False
        lin, ang = self.speeds()
        return (lin < self.rest_speed_mps and ang < self.rest_angular_speed_rad_s
                and not self.touched_by_robot())

    def where(self) -> str:
        """Where the target is, in words: ``in the tray``, ``in the tray, still moving``,
        ``in the tray, touched by the robot``, ``held up``, ``off the table``, ``on the
        table``."""
        p = self.position_m()
        if self.in_tray():
            if self.touched_by_robot():
                return "in the tray, touched by the robot"
            lin, ang = self.speeds()
            if lin >= self.rest_speed_mps or ang >= self.rest_angular_speed_rad_s:
                return "in the tray, still moving"
            return "in the tray"
        if p[2] < self.table_top_z - FALLEN_BELOW_M:
            return "off the table"
        if p[2] > self.z0 + LIFTED_M:
            return "held up" if self.touched_by_robot() else "up in the air"
        return "on the table"
