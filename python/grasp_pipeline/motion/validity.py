"""State validity for planning: joint limits + self-collision + perceived environment.

A joint state is valid when
* every joint is within ``[q_min, q_max]``;
* no checked pair of robot spheres (non-adjacent links, see :mod:`.robot_spheres`) is closer
  than ``self_collision_margin_m``;
* every sphere of a moving link keeps ``collision_margin_m`` from the occupancy map (the
  map's conservative voxel inflation included), from every non-target object box, and stays
  above the floor plane ``floor_z_m``.

With ``allow_target_contact=True`` (the final Cartesian approach and the lift) the spheres
of the flange subtree (link 7, hand, fingers, camera) use the map view in which the target
box (inflated by ``target_ignore_padding_m``) is free: the fingers may enter the target's
region and come close to the table right beside it. Everything else is unchanged.

Obstacles come only from perception (environment points, object boxes): never from the
simulator's ground truth.

The checks run in the C++ core (``_core.StateChecker``, built by :mod:`.core_checker`):
``check_batch`` / ``is_valid`` / ``check_segment`` delegate to it. The numpy implementation
stays as the reference (:meth:`StateValidator._python_check_batch`, and :meth:`explain`);
the tests compare both on random and near-boundary states.
"""

from __future__ import annotations

import numpy as np

from .. import _core
from ..robot import description as rm
from . import core_checker
from .config import MotionConfig
from .object_points import ObjectPoints
from .occupancy import OccupancyMap, OrientedBox
from .robot_spheres import RobotSpheres


class StateValidator:
    """Batch and single-state validity of arm joint states against one perceived scene."""

    def __init__(self, robot: RobotSpheres, config: MotionConfig,
                 env: OccupancyMap | None = None, boxes: list[OrientedBox] | None = None,
                 target_box: OrientedBox | None = None) -> None:
        self.robot = robot
        self.config = config
        self.q_min = np.asarray(rm.PANDA_Q_MIN, dtype=float)
        self.q_max = np.asarray(rm.PANDA_Q_MAX, dtype=float)
        self._sphere_masks()
        self._checked_before = 0
        self._core_gap_m: float | None = None
        self._core_version = -1
        self._core = None
        self._scene = None
        self._scene_inputs: tuple = ()
        self._allow_target = False
        self.set_scene(env, boxes or [], target_box)

    def _sphere_masks(self) -> None:
        sph = self.robot.spheres
        self._env_idx = np.nonzero(self.robot.env_mask)[0]
        self._env_r = sph.radius[self._env_idx]
        self._env_hand = self.robot.hand_mask[self._env_idx]
        self._masks_version = self.robot.version
        if hasattr(self, "env"):
            self._thresholds()

    def _thresholds(self) -> None:
        env = self.env
        self._env_thr = self._env_r + self.config.collision_margin_m + (env.inflation_m if env else 0.0)
        self._box_thr = self._env_r + self.config.collision_margin_m

    # ------------------------------------------------------------------ C++ checker
    def core(self):
        """The ``_core.StateChecker`` of the current scene (rebuilt after a finger-opening
        change or an attach / detach)."""
        if self._masks_version != self.robot.version:
            self._sphere_masks()
        if self._core is None or self._core_gap_m != self.robot.finger_opening_m \
                or self._core_version != self.robot.version:
            if self._core is not None:
                self._checked_before += int(self._core.checked_states)
            model = core_checker.robot_model(self.robot, self.q_min, self.q_max)
            self._core = _core.StateChecker(model, self._scene)
            self._core.allow_target_contact = self._allow_target
            self._core_gap_m = self.robot.finger_opening_m
            self._core_version = self.robot.version
        return self._core

    @property
    def allow_target_contact(self) -> bool:
        """Hand spheres may enter the (padded) target box region (final approach, lift)."""
        return self._allow_target

    @allow_target_contact.setter
    def allow_target_contact(self, allow: bool) -> None:
        self._allow_target = bool(allow)
        if self._core is not None:
            self._core.allow_target_contact = self._allow_target

    @property
    def checked_states(self) -> int:
        """States evaluated so far (a segment check stops at its first invalid state)."""
        return self._checked_before + (int(self._core.checked_states) if self._core is not None else 0)

    # ------------------------------------------------------------------ scene
    def required_pad_m(self) -> float:
        """Distance-field padding an occupancy map needs for these checks."""
        v = self.config.voxel_size_m
        return float(self._env_r.max() + self.config.collision_margin_m + np.sqrt(3.0) * v + v)

    def required_points_pad_m(self, fine_m: float) -> float:
        """The reach point-obstacle queries need: the largest sphere's radius + margin + the
        points' rounding ``fine_m``, plus a millimetre."""
        return float(self._env_r.max() + self.config.collision_margin_m + fine_m + 1e-3)

    def set_scene(self, env: OccupancyMap | None, boxes: list[OrientedBox],
                  target_box: OrientedBox | None = None, points: ObjectPoints | None = None) -> None:
        """Obstacles: the environment map, the non-target boxes, the objects modelled by their
        points (never cleared: a neighbour stays an obstacle in the final approach), and
        (optionally) the target box whose padded region the hand may enter when
        ``allow_target_contact`` is set."""
        self.env = env
        self.boxes = list(boxes)
        self.points = points if points is not None and len(points.points) else None
        self.target_box = target_box
        self._env_cleared = None
        if env is not None and target_box is not None:
            self._env_cleared = env.with_cleared_region(
                target_box.inflated(self.config.target_ignore_padding_m))
        self._thresholds()
        inputs = (env, self._env_cleared, self.points, *self.boxes)
        if not _same_objects(inputs, self._scene_inputs):
            self._scene = core_checker.collision_scene(self.config, env, self.boxes, self._env_cleared,
                                                       self.points)
            self._scene_inputs = inputs
        if self._core is not None:
            self._core.set_scene(self._scene)

    # ------------------------------------------------------------------ checks
    def _components(self, Q: np.ndarray):
        """Per-state margins: limits ok (N,), self clearance (N,), env slack (N, Se),
        box slack (N, Se), floor slack (N, Se) and the sphere centres."""
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        if self._masks_version != self.robot.version:
            self._sphere_masks()
        lim_ok = np.all((Q >= self.q_min) & (Q <= self.q_max), axis=1)
        C = self.robot.centres(Q)
        self_min = self.robot.self_clearance_min(C)
        E = C[:, self._env_idx]  # (N, Se, 3)
        n, se = E.shape[:2]
        flat = E.reshape(-1, 3)
        if self.env is not None:
            d = self.env.distance_m(flat).reshape(n, se)
            if self.allow_target_contact and self._env_cleared is not None:
                hand = np.broadcast_to(self._env_hand, (n, se))
                dh = self._env_cleared.distance_m(flat[hand.reshape(-1)], cleared=True)
                d[hand] = dh
            env_slack = d - self._env_thr
        else:
            env_slack = np.full((n, se), np.inf)
        db = np.full(len(flat), np.inf)
        for b in self.boxes:
            db = np.minimum(db, b.distance_m(flat))
        if self.points is not None:
            db = np.minimum(db, self.points.distance_m(flat))
        box_slack = db.reshape(n, se) - self._box_thr
        floor_slack = E[..., 2] - self._env_r - self.config.floor_z_m
        return lim_ok, self_min, env_slack, box_slack, floor_slack, C

    def check_batch(self, Q: np.ndarray) -> np.ndarray:
        """(N,) True where the state (row of Q (N, 7), rad) is valid; rows with NaN/Inf are invalid."""
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        finite = np.all(np.isfinite(Q), axis=-1)
        if finite.all():
            return self.core().check_batch(Q)
        out = np.zeros(len(Q), dtype=bool)
        out[finite] = self.core().check_batch(Q[finite])
        return out

    def _python_check_batch(self, Q: np.ndarray) -> np.ndarray:
        """The numpy reference of :meth:`check_batch` (same semantics, ~100x slower)."""
        lim_ok, self_min, env_slack, box_slack, floor_slack, _ = self._components(Q)
        return (lim_ok & (self_min >= self.config.self_collision_margin_m)
                & np.all(env_slack >= 0, axis=1) & np.all(box_slack >= 0, axis=1)
                & np.all(floor_slack >= 0, axis=1))

    def is_valid(self, q: np.ndarray) -> bool:
        q = np.asarray(q, dtype=float).reshape(-1)
        return bool(np.all(np.isfinite(q))) and bool(self.core().check(q))

    def segment_states(self, qa: np.ndarray, qb: np.ndarray, max_step_rad: float,
                       include_start: bool = False) -> np.ndarray:
        """States along the straight joint line, no joint moving more than ``max_step_rad``."""
        qa, qb = np.asarray(qa, dtype=float), np.asarray(qb, dtype=float)
        n = max(1, int(np.ceil(np.max(np.abs(qb - qa)) / max_step_rad)))
        s = np.arange(0 if include_start else 1, n + 1)[:, None] / n
        return qa + (qb - qa) * s

    def check_segment(self, qa: np.ndarray, qb: np.ndarray, max_step_rad: float,
                      include_start: bool = False) -> bool:
        """True if every state on the line (step ≤ ``max_step_rad`` per joint) is valid
        (C++: coarse-to-fine order, stops at the first invalid state)."""
        qa, qb = np.asarray(qa, dtype=float).reshape(-1), np.asarray(qb, dtype=float).reshape(-1)
        if not (np.all(np.isfinite(qa)) and np.all(np.isfinite(qb))):
            return False
        return bool(self.core().check_segment(qa, qb, max_step_rad, include_start))

    def check_path(self, waypoints: np.ndarray, max_step_rad: float) -> int | None:
        """Index of the first segment with an invalid state (dense check), or None."""
        wp = np.asarray(waypoints, dtype=float)
        if not self.is_valid(wp[0]):
            return 0
        for k in range(len(wp) - 1):
            if not self.check_segment(wp[k], wp[k + 1], max_step_rad):
                return k
        return None

    def first_invalid_state(self, waypoints: np.ndarray, max_step_rad: float) -> tuple[int, np.ndarray] | None:
        """(segment, state) of the first invalid state of the densified polyline after its first
        waypoint (the states of :meth:`segment_states`, in path order; one C++ call), or None."""
        wp = np.asarray(waypoints, dtype=float)
        seg, i = self.core().first_invalid_on_path(wp, max_step_rad)
        if seg < 0:
            return None
        return int(seg), self.segment_states(wp[seg], wp[seg + 1], max_step_rad)[i]

    def explain(self, q: np.ndarray) -> str:
        """Human-readable reason why ``q`` is invalid ("valid" if it is not)."""
        q = np.asarray(q, dtype=float)
        lim_ok, self_min, env_slack, box_slack, floor_slack, C = self._components(q[None])
        m = self.robot.model
        reasons = []
        if not lim_ok[0]:
            bad = np.nonzero((q < self.q_min) | (q > self.q_max))[0]
            reasons += [f"joint {j + 1} = {q[j]:.4f} rad outside [{self.q_min[j]:.4f}, {self.q_max[j]:.4f}]"
                        for j in bad]
        if self_min[0] < self.config.self_collision_margin_m:
            c = C[0]
            d = np.linalg.norm(c[self.robot.pair_i] - c[self.robot.pair_j], axis=1) - self.robot.pair_rsum
            k = int(np.argmin(d))
            a = m.body(int(self.robot.spheres.body[self.robot.pair_i[k]])).name
            b = m.body(int(self.robot.spheres.body[self.robot.pair_j[k]])).name
            reasons.append(f"self-collision between {a} and {b} ({-d[k] * 1e3:.1f} mm overlap)")
        names = [m.body(int(b)).name for b in self.robot.spheres.body[self._env_idx]]
        for label, slack in (("perceived environment (occupancy map)", env_slack[0]),
                             ("a non-target object box (or an object's points)", box_slack[0]), ("the floor", floor_slack[0])):
            if np.any(slack < 0):
                k = int(np.argmin(slack))
                p = C[0, self._env_idx[k]]
                reasons.append(f"{names[k]} within the clearance of {label} by {-slack[k] * 1e3:.1f} mm "
                               f"near ({p[0]:.3f}, {p[1]:.3f}, {p[2]:.3f}) m")
        return "; ".join(reasons) if reasons else "valid"


def _same_objects(a: tuple, b: tuple) -> bool:
    """Whether two tuples hold the very same objects (the collision scene built from one
    stands for the other: maps, views, boxes and point sets are not changed once made)."""
    return len(a) == len(b) and all(x is y for x, y in zip(a, b))
