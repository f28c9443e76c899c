"""The planner's world by name: what the arm must avoid, what the hand may touch, what it holds.

Like a planning scene in MoveIt or MPlib's planning world, the obstacles are named:

* the **environment**: the perceived points that belong to no object (table, floor, walls),
  as an occupancy map, with the arm's joints at capture for the robot's self-filter;
* **objects** by name — ``object/<track id>`` for the perceived ones (modelled by their
  points where seen well enough, else by their boxes; see :mod:`.object_points`), and any
  the caller adds, e.g. ``placed/<k>`` for what the robot put into the tray;
* **fixtures** of the work cell (the tray's walls), ``fixture/<k>``;
* the **attached** object: what the hand holds, carried with the hand (spheres fixed to the
  hand, checked like the hand) from when it leaves the table until it is released.

**Allowed collisions**: one object may be touched by the hand — the grasp target, whose
region (its box grown by ``target_ignore_padding_m``) the hand and fingers may enter during
the motions that ask for it (the final approach, the lift). Every other pair stays checked.
Changes are pushed to the :class:`~.motion_planner.MotionPlanner` on :meth:`PlanningWorld.commit`
(the occupancy map is rebuilt only when the environment changed).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Sequence

import numpy as np

from ..array_rows import rows_where
from ..robot import description as rm
from .object_points import PointModel
from .occupancy import OrientedBox
from .perceived_scene import PerceivedScene

PERCEIVED_PREFIX = "object/"
FIXTURE_PREFIX = "fixture/"
#: Cell of the grid whose occupied cells each get a sphere covering an attached object [m].
ATTACH_CELL_M = 0.02


@dataclass(frozen=True)
class WorldObject:
    """One named obstacle: its ``box``; ``tops`` the column tops when it is modelled by its
    points (an empty array: no obstacle of its own), None when modelled by its box."""

    name: str
    box: OrientedBox
    tops: Optional[np.ndarray] = None


class PlanningWorld:
    """Named obstacles, the touchable target and the attached object of one planner."""

    def __init__(self, planner, fixtures: Sequence[OrientedBox] = ()) -> None:
        self.planner = planner
        self.points_model = PointModel.from_motion(planner.config)
        self.fixtures = {f"{FIXTURE_PREFIX}{k}": WorldObject(f"{FIXTURE_PREFIX}{k}", b)
                         for k, b in enumerate(fixtures)}
        self.objects: dict[str, WorldObject] = {}
        self.environment = np.zeros((0, 3))
        self.capture_q: Optional[np.ndarray] = None
        self.plane = None
        self.band_m = 0.0  # the perceived scene's band above the plane: lower points are the table's
        self.touchable: Optional[str] = None
        self._env_dirty = True

    # ------------------------------------------------------------------ perceived
    def set_perceived(self, scene: PerceivedScene) -> None:
        """The environment and the ``object/<tid>`` entries from one perceived scene (the
        objects the caller added under other names stay)."""
        env = np.asarray(scene.environment_points, dtype=float).reshape(-1, 3)
        q = None if scene.capture_q is None else np.asarray(scene.capture_q, float)
        same = (env.shape == self.environment.shape and np.array_equal(env, self.environment)
                and (q is None) == (self.capture_q is None)
                and (q is None or np.array_equal(q, self.capture_q)))
        self.environment, self.capture_q, self.plane, self.band_m = env, q, scene.plane, scene.band_m
        self._env_dirty = self._env_dirty or not same  # the same frame: the map stands
        kept = {n: o for n, o in self.objects.items() if not n.startswith(PERCEIVED_PREFIX)}
        tops = scene.object_tops(self.points_model)
        perceived = {f"{PERCEIVED_PREFIX}{tid}": WorldObject(f"{PERCEIVED_PREFIX}{tid}", box, top)
                     for tid, box, top in zip(scene.tids, scene.boxes, tops)}
        self.objects = {**perceived, **kept}
        if self.touchable is not None and self.touchable not in self.objects:
            self.touchable = None

    # ------------------------------------------------------------------ objects
    def add_object(self, name: str, box: OrientedBox, tops: Optional[np.ndarray] = None) -> None:
        """Add (or replace) a named obstacle, e.g. an object placed into the tray."""
        if name.startswith(FIXTURE_PREFIX):
            raise ValueError(f"object names starting with {FIXTURE_PREFIX!r} are the work cell's")
        self.objects[name] = WorldObject(name, box, tops)

    def remove_object(self, name: str) -> None:
        self.objects.pop(name, None)
        if self.touchable == name:
            self.touchable = None

    def names(self) -> list[str]:
        return list(self.objects) + list(self.fixtures)

    def allow_touching(self, name: Optional[str]) -> None:
        """The object the hand may touch (its padded region), or None."""
        if name is not None and name not in self.objects:
            raise KeyError(f"no object {name!r} in the planning world (have: {', '.join(self.objects)})")
        self.touchable = name

    # ------------------------------------------------------------------ attached
    def attach(self, name: str, points_world: np.ndarray, T_world_tcp: np.ndarray,
               cell_m: float = ATTACH_CELL_M) -> int:
        """Attach what the hand holds: ``points_world`` (N, 3) of it at the TCP pose
        ``T_world_tcp``, covered by spheres (one per ``cell_m`` cell, each holding its cell's
        points). Removes the object ``name`` from the obstacles, and the environment points in
        the region it stood in (above the table). Returns the sphere count."""
        pts = np.asarray(points_world, dtype=float).reshape(-1, 3)
        pts = pts[np.all(np.isfinite(pts), axis=1)]
        if len(pts) == 0:
            return 0
        T_world_hand = np.asarray(T_world_tcp, float) @ _tcp_T_hand(self.planner.model)
        local = (pts - T_world_hand[:3, 3]) @ T_world_hand[:3, :3]
        centres, radii = _cover(local, cell_m)
        self.planner.robot.attach(name, centres, radii)
        if name in self.objects:
            self._clear_environment(self.objects[name].box)
        self.remove_object(name)
        return len(radii)

    def _clear_environment(self, box: OrientedBox) -> None:
        """Drop the environment points in the region the held object stood in (its box grown
        by a voxel), except the table's (less than the scene's ``band_m`` above the plane):
        stray points of the object that no track took would otherwise stay where it stood
        and meet it when it is lifted."""
        env = self.environment
        if not len(env):
            return
        inside = box.inflated(float(self.planner.config.voxel_size_m)).contains(env)
        if self.plane is not None:
            inside &= env @ np.asarray(self.plane.n, float) + float(self.plane.c) > self.band_m
        if np.any(inside):
            self.environment = rows_where(env, ~inside)
            self._env_dirty = True

    def detach(self) -> Optional[str]:
        """Release what the hand holds (its spheres leave the hand); returns its name."""
        return self.planner.robot.detach()

    def trim_attached(self, q: np.ndarray) -> int:
        """Drop the attached spheres that lie within an obstacle's clearance with the arm at
        ``q`` while the hand holds the object free of it (lifted): those parts of its model
        were filled in under what was seen — e.g. down through the object it lay on in a pile.
        Returns how many were dropped (call :meth:`commit` after)."""
        robot, v = self.planner.robot, self.planner.validator
        if robot.attached_name is None:
            return 0
        _, _, env, box, floor, _ = v._components(np.asarray(q, float)[None])
        inside = np.zeros(len(robot.spheres.radius), dtype=bool)
        inside[v._env_idx] = (env[0] < 0) | (box[0] < 0) | (floor[0] < 0)
        held = robot.spheres.geom == self.planner.model.ngeom
        if not np.any(inside & held):
            return 0
        keep = held & ~inside
        name, sph = robot.attached_name, robot.spheres
        robot.detach()
        if np.any(keep):
            robot.attach(name, sph.center_local[keep], sph.radius[keep])
        return int(np.count_nonzero(inside & held))

    @property
    def attached(self) -> Optional[str]:
        return self.planner.robot.attached_name

    # ------------------------------------------------------------------ planner
    def commit(self) -> None:
        """Push the world to the planner (the occupancy map only when it changed)."""
        entries = list(self.objects.values()) + list(self.fixtures.values())
        boxes = [o.box for o in entries]
        tops = [o.tops for o in entries]
        target = None if self.touchable is None else list(self.objects).index(self.touchable)
        if self._env_dirty:
            self.planner.set_scene(self.environment, boxes, capture_q=self.capture_q,
                                   target_index=target, object_tops=tops, plane=self.plane)
            self._env_dirty = False
        else:
            self.planner.set_objects(boxes, tops, target)


def held_spheres_in_tcp(model, points_tcp: np.ndarray, cell_m: float = ATTACH_CELL_M
                        ) -> tuple[np.ndarray, np.ndarray]:
    """The spheres :meth:`PlanningWorld.attach` covers a held object with, for its points
    ``points_tcp`` (N, 3) in the TCP frame: centres (M, 3) in the TCP frame and radii (M,)."""
    T = _tcp_T_hand(model)
    pts = np.asarray(points_tcp, dtype=float).reshape(-1, 3)
    centres, radii = _cover((pts - T[:3, 3]) @ T[:3, :3], cell_m)
    return centres @ T[:3, :3].T + T[:3, 3], radii


def _tcp_T_hand(model) -> np.ndarray:
    """Pose of the hand body in the TCP frame."""
    return np.linalg.inv(rm.flange_T_tcp(model)) @ _flange_T_hand(model)


def _flange_T_hand(model) -> np.ndarray:
    """Pose of the hand body in the flange frame."""
    from ..robot.description import _body_T_in_flange

    return _body_T_in_flange(model, model.body(rm.HAND_BODY).id)


def _cover(points: np.ndarray, cell_m: float) -> tuple[np.ndarray, np.ndarray]:
    """Spheres covering ``points``: per ``cell_m`` cell, centred on the cell's points' mean,
    radius the farthest of them plus a millimetre."""
    key = np.floor(points / cell_m).astype(np.int64)
    _, inv = np.unique(key, axis=0, return_inverse=True)
    inv = inv.reshape(-1)
    n = int(inv.max()) + 1
    sums = np.zeros((n, 3))
    np.add.at(sums, inv, points)
    centres = sums / np.bincount(inv, minlength=n)[:, None]
    far = np.zeros(n)
    np.maximum.at(far, inv, np.linalg.norm(points - centres[inv], axis=1))
    return centres, far + 1e-3
