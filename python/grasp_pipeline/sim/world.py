"""The simulated world: Panda + hand + depth camera + table scene, stepped in MuJoCo.

:class:`SimWorld` builds an ``MjModel`` from ``sim/scene_base.xml`` (robot, table, wall, tray)
plus the objects of a :class:`~.scene_spec.SceneSpec` (added with ``MjSpec``), then offers:

* stepping (``step``, ``run_until``) at the physics step of ``sim.yaml`` (2 ms);
* arm control: a time-stamped joint trajectory (``follow_trajectory``) is interpolated every
  step (cubic Hermite when velocities are given, else linear) and fed to the joint PD servos
  (position actuators, ``ctrl = q_ref + (kv/kp) qd_ref`` so the servo also tracks the
  reference velocity); gravity is compensated by the model (``gravcomp``);
* the gripper: ``set_gripper(width_m, effort_N)`` moves the commanded finger gap at
  ``gripper_speed_mps`` towards the target; the single actuator's force (the squeeze force) is
  limited to the effort, so closing on an object stalls there and holds by friction;
* readouts (joints, velocities, finger gap and speed, flange/TCP/camera poses), contacts of
  robot geoms with non-robot geoms, and depth frames (``capture``, ``poll_frame``) at the
  camera rate in simulated time;
* frames on demand (``camera.yaml`` ``frames: on_demand``): frame listeners are fed only
  while someone requested frames (``with world.request_frames(): ...``, counted and
  nestable), so motions during which nobody looks run without rendering;
  ``frames: continuous`` renders whenever a listener exists (the old path).

Ground truth about objects is deliberately *not* offered here; evaluation code reads it
through :mod:`grasp_pipeline.sim.ground_truth`.
"""

from __future__ import annotations

import logging
import math
from contextlib import contextmanager
from typing import Callable, Iterator

import mujoco
import numpy as np

from ..assets import asset_path
from .camera import DepthCamera
from .config import CameraConfig, SimConfig, load_camera_config, load_sim_config
from .exceptions import GripperError, ModelError, TrajectoryError
from .joint_reference import TrajectoryReference
from ..robot.depth_noise import DepthNoiseConfig
from ..robot.frame import Frame
from ..robot.description import (
    BASE_BODY,
    FINGER_GAP_TENDON,
    FINGER_JOINT_NAMES,
    FLANGE_BODY,
    GRIPPER_ACTUATOR,
    GRIPPER_MAX_FORCE_N,
    GRIPPER_MAX_WIDTH_M,
    PANDA_ACTUATOR_NAMES,
    PANDA_Q_MAX,
    PANDA_Q_MIN,
    TCP_SITE,
    arm_dof_indices,
    arm_qpos_indices,
)
from .object_geoms import OBJECT_PREFIX, add_object, geom_object
from .scene_spec import SceneSpec
from .scenes import reference_scene
from .work_cell import SCENE_BASE_XML, TABLE_TOP_GEOM, read_work_cell
from ..motion.work_cell import WorkCell
from ..robot.protocols import ContactAllowance

log = logging.getLogger(__name__)

#: Robot geoms whose name contains this are fingers (pads and finger bodies).
FINGER_GEOM_MARK = "finger"
#: How far outside the joint limits a trajectory point may lie (numerical slack) [rad].
TRAJECTORY_LIMIT_SLACK_RAD = 1e-3
#: Table height check tolerance [m].
TABLE_TOP_TOLERANCE_M = 1e-6
#: Fingers commanded shut and at least this far apart hold an object (closer: shut on nothing) [m].
_HOLDING_MIN_GAP_M = 0.004


def _as_slice(idx: np.ndarray) -> slice | np.ndarray:
    """A slice for consecutive indices (cheaper to read and write at every step), else ``idx``."""
    idx = np.asarray(idx)
    if len(idx) and np.array_equal(idx, np.arange(idx[0], idx[0] + len(idx))):
        return slice(int(idx[0]), int(idx[0]) + len(idx))
    return idx


def build_scene_model(scene: SceneSpec, config: SimConfig) -> mujoco.MjModel:
    """Compile robot + fixed set-up + the scene's objects into one ``MjModel``."""
    spec = mujoco.MjSpec.from_file(str(asset_path(SCENE_BASE_XML)))
    for obj in scene.objects:
        add_object(spec, obj, config)
    try:
        model = spec.compile()
    except Exception as exc:
        raise ModelError(f"cannot compile scene {scene.name!r}: {exc}") from exc
    model.opt.timestep = config.timestep_s
    model.opt.noslip_iterations = config.noslip_iterations
    return model


class SimWorld:
    """A running simulation of one scene; implements the robot protocols of
    :mod:`grasp_pipeline.robot.protocols` (clock, arm, gripper, camera, contact monitor).

    Args:
        scene: what stands on the table (default: :func:`~.scenes.reference_scene`).
        sim_config: physics/gripper parameters (default: ``config/sim.yaml``).
        camera_config: depth camera parameters (default: ``config/camera.yaml``).
        camera: create the depth camera (False for physics-only use; ``capture`` then raises).
        depth_noise: the camera's noise model (default: ``config/depth_noise.yaml``; perception
            must be given the same, see :mod:`grasp_pipeline.robot.depth_noise`).

    The arm starts at ``scene.start_q`` holding still, the gripper fully open.
    Use as a context manager or call :meth:`close` to free the camera's GL context.
    """

    def __init__(self, scene: SceneSpec | None = None, sim_config: SimConfig | None = None,
                 camera_config: CameraConfig | None = None, camera: bool = True,
                 depth_noise: DepthNoiseConfig | None = None):
        self.config = sim_config if sim_config is not None else load_sim_config()
        self.scene = scene if scene is not None else reference_scene(self.config)
        self.model = build_scene_model(self.scene, self.config)
        self.data = mujoco.MjData(self.model)
        m = self.model
        self._qpos_idx = _as_slice(arm_qpos_indices(m))
        self._dof_idx = _as_slice(arm_dof_indices(m))
        act_ids = np.array([m.actuator(n).id for n in PANDA_ACTUATOR_NAMES])
        self._act_idx = _as_slice(act_ids)
        self._kv_over_kp = np.array([-m.actuator_biasprm[a, 2] / m.actuator_gainprm[a, 0]
                                     for a in act_ids])
        self._grip_act = m.actuator(GRIPPER_ACTUATOR).id
        self._gap_tendon = m.tendon(FINGER_GAP_TENDON).id
        self._finger_dofs = np.array([m.joint(n).dofadr[0] for n in FINGER_JOINT_NAMES])
        self._finger_qpos = np.array([m.joint(n).qposadr[0] for n in FINGER_JOINT_NAMES])
        self._flange_body = m.body(FLANGE_BODY).id
        self._tcp_site = m.site(TCP_SITE).id
        base_root = m.body(BASE_BODY).id
        self._robot_geom = m.body_rootid[m.geom_bodyid] == base_root
        self._geom_names: list[str] | None = None
        # (contact key, robot contacts by name) and (allowance, contact key, verdict) of the
        # latest contacts asked about: see _contact_key
        self._contacts_memo: tuple[bytes, list[tuple[str, str]]] = (b"", [])
        self._unexpected_memo: tuple[ContactAllowance | None, bytes, list[str]] = (None, b"", [])
        self._check_table_height()

        start_q = np.asarray(self.scene.start_q, dtype=float)
        self.data.qpos[self._qpos_idx] = start_q
        self.data.qpos[self._finger_qpos] = GRIPPER_MAX_WIDTH_M / 2
        self._traj: TrajectoryReference | None = None
        self._ref = self._held(start_q.copy())  # what the servos follow: the trajectory or a hold
        self._grip_target_m = GRIPPER_MAX_WIDTH_M
        self._grip_cmd_m = GRIPPER_MAX_WIDTH_M
        self._grip_speed_mps = self.config.gripper_speed_mps
        self._noslip_base = self.config.noslip_iterations
        self._noslip_hold = self.config.noslip_hold_iterations
        # read and written at every physics step, so made once (MuJoCo's accessors build a new
        # wrapper at each access): the solver options and the controls
        self._opt = m.opt
        self._noslip_now = int(self._opt.noslip_iterations)
        self._ctrl = self.data.ctrl
        self._set_grip_effort(self.config.gripper_default_effort_N)
        self._apply_controls()
        mujoco.mj_forward(m, self.data)

        cam_cfg = camera_config if camera_config is not None else load_camera_config()
        self.camera_config = cam_cfg
        self.camera: DepthCamera | None = (DepthCamera(m, self.data, cam_cfg, depth_noise=depth_noise)
                                           if camera else None)
        self._next_frame_time_s = float(self.data.time)
        self._frame_listeners: list[Callable[[Frame], None]] = []
        self._continuous_frames = cam_cfg.frames == "continuous"
        self._frame_requests = 0
        self._looking_time_s = 0.0

    # ------------------------------------------------------------------ lifecycle
    def close(self) -> None:
        """Free the camera's GL context."""
        if self.camera is not None:
            self.camera.close()

    def __enter__(self) -> "SimWorld":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _check_table_height(self) -> None:
        g = self.model.geom(TABLE_TOP_GEOM)
        top = float(g.pos[2] + g.size[2])
        if abs(top - self.scene.table_top_z_m) > TABLE_TOP_TOLERANCE_M:
            raise ModelError(f"table top in {SCENE_BASE_XML} is at {top:.4f} m but the scene "
                             f"expects {self.scene.table_top_z_m:.4f} m (its table_top_z_m)")

    # ------------------------------------------------------------------ readouts
    @property
    def time_s(self) -> float:
        """Simulated time [s]."""
        return float(self.data.time)

    @property
    def timestep_s(self) -> float:
        return float(self.model.opt.timestep)

    @property
    def q(self) -> np.ndarray:
        """Arm joint positions (7,) [rad] (a copy)."""
        return self.data.qpos[self._qpos_idx].copy()

    @property
    def qd(self) -> np.ndarray:
        """Arm joint velocities (7,) [rad/s] (a copy)."""
        return self.data.qvel[self._dof_idx].copy()

    @property
    def finger_gap_m(self) -> float:
        """Distance between the two fingertip pads [m] (0 closed, 0.08 fully open)."""
        return float(self.data.ten_length[self._gap_tendon])

    @property
    def finger_speed_mps(self) -> float:
        """Speed of one finger [m/s], signed: > 0 opening, < 0 closing (half the gap rate).
        method.md §7's stall test compares ``abs(finger_speed_mps)`` with 0.005 m/s."""
        return float(0.5 * self.data.ten_velocity[self._gap_tendon])

    @property
    def gripper_target_m(self) -> float:
        """The finger gap last commanded with :meth:`set_gripper` [m]."""
        return self._grip_target_m

    @property
    def gripper_force_N(self) -> float:
        """Force of the gripper actuator (the squeeze force on a held object) [N], >= 0."""
        return float(-self.data.actuator_force[self._grip_act])

    def flange_pose(self) -> np.ndarray:
        """World pose (4x4) of the flange."""
        T = np.eye(4)
        T[:3, :3] = self.data.xmat[self._flange_body].reshape(3, 3)
        T[:3, 3] = self.data.xpos[self._flange_body]
        return T

    def tcp_pose(self) -> np.ndarray:
        """World pose (4x4) of the TCP (between the fingertips; z = approach)."""
        T = np.eye(4)
        T[:3, :3] = self.data.site_xmat[self._tcp_site].reshape(3, 3)
        T[:3, 3] = self.data.site_xpos[self._tcp_site]
        return T

    def camera_pose(self) -> np.ndarray:
        """World pose (4x4) of the camera optical frame now."""
        if self.camera is None:
            raise ModelError("this SimWorld was created with camera=False")
        return self.camera.pose()

    # ------------------------------------------------------------------ arm control
    def follow_trajectory(self, t_s: np.ndarray, q: np.ndarray, qd: np.ndarray | None = None,
                          start_time_s: float | None = None) -> float:
        """Set the arm's reference to a time-stamped joint trajectory; returns its end time.

        Non-blocking: the reference is followed by subsequent :meth:`step` calls.

        Args:
            t_s: (K,) strictly increasing times [s], relative to ``start_time_s``
                (usually starting at 0).
            q: (K, 7) joint positions [rad], within the Panda's limits.
            qd: optional (K, 7) joint velocities [rad/s]; with them the reference is a cubic
                Hermite spline, without them piecewise linear.
            start_time_s: absolute simulated time of ``t_s = 0``; default: now.

        Before the first sample the arm holds ``q[0]``; after the last it holds ``q[-1]``.
        A new call replaces the previous trajectory.
        """
        t = np.asarray(t_s, dtype=float).reshape(-1)
        qq = np.asarray(q, dtype=float)
        if qq.ndim != 2 or qq.shape[1] != 7 or qq.shape[0] != t.shape[0] or t.size == 0:
            raise TrajectoryError(f"need t_s (K,) and q (K, 7); got {t.shape} and {qq.shape}")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(qq))):
            raise TrajectoryError("trajectory contains NaN or Inf")
        if t.size > 1 and np.any(np.diff(t) <= 0):
            raise TrajectoryError("trajectory times must be strictly increasing")
        slack = TRAJECTORY_LIMIT_SLACK_RAD
        bad = np.any((qq < PANDA_Q_MIN - slack) | (qq > PANDA_Q_MAX + slack), axis=0)
        if np.any(bad):
            raise TrajectoryError(f"trajectory leaves the joint limits of joints "
                                  f"{[int(i) + 1 for i in np.flatnonzero(bad)]}")
        qdd = None
        if qd is not None:
            qdd = np.asarray(qd, dtype=float)
            if qdd.shape != qq.shape or not np.all(np.isfinite(qdd)):
                raise TrajectoryError(f"qd must be finite with shape {qq.shape}, got {qdd.shape}")
        t0 = self.time_s if start_time_s is None else float(start_time_s)
        self._traj = TrajectoryReference(t + t0, qq.copy(), None if qdd is None else qdd.copy(),
                                         self._kv_over_kp, self.timestep_s)
        self._ref = self._traj
        return self._traj.end_time_s

    def hold(self, q: np.ndarray | None = None) -> None:
        """Drop the trajectory and hold ``q`` (default: the current joints)."""
        self._traj = None
        self._ref = self._held(self.q if q is None else np.asarray(q, dtype=float).reshape(7).copy())

    def _held(self, q: np.ndarray) -> TrajectoryReference:
        """The reference of holding ``q`` (one sample: ``q`` at any time, zero velocity)."""
        return TrajectoryReference(np.array([self.time_s]), q[None, :], None, self._kv_over_kp,
                                   self.timestep_s)

    @property
    def trajectory_end_time_s(self) -> float | None:
        """End time of the active trajectory (absolute), or None when holding."""
        return None if self._traj is None else self._traj.end_time_s

    def trajectory_done(self) -> bool:
        """True when no trajectory is active or its last sample time has passed."""
        return self._traj is None or self.time_s >= self._traj.end_time_s

    def reference(self, t: float | None = None) -> tuple[np.ndarray, np.ndarray]:
        """The joint reference (q_ref, qd_ref) at time ``t`` (default: now); read-only arrays."""
        return self._ref.sample(self.time_s if t is None else t)

    # ------------------------------------------------------------------ gripper
    def _set_grip_effort(self, effort_N: float) -> None:
        self.model.actuator_forcerange[self._grip_act] = (-effort_N, effort_N)

    def set_gripper(self, width_m: float, effort_N: float | None = None,
                    speed_mps: float | None = None) -> None:
        """Command the finger gap (non-blocking).

        Args:
            width_m: target gap between the pads, 0 .. 0.08 m. Closing on an object, command
                less than its width: the fingers stall on it and squeeze with ``effort_N``.
            effort_N: force limit of the gripper actuator = squeeze force at a stall
                (default ``sim.yaml`` ``gripper_default_effort_N``; at most the hand's
                ``GRIPPER_MAX_FORCE_N``, robot/limits.py).
            speed_mps: rate at which the commanded gap moves (default ``gripper_speed_mps``).
        """
        if not (0.0 <= width_m <= GRIPPER_MAX_WIDTH_M + 1e-9) or not math.isfinite(width_m):
            raise GripperError(f"gripper width must be within 0..{GRIPPER_MAX_WIDTH_M} m, got {width_m}")
        effort = self.config.gripper_default_effort_N if effort_N is None else float(effort_N)
        if not 0.0 < effort <= GRIPPER_MAX_FORCE_N:
            raise GripperError(f"gripper effort must be in (0, {GRIPPER_MAX_FORCE_N:g}] N,"
                               f" got {effort}")
        speed = self.config.gripper_speed_mps if speed_mps is None else float(speed_mps)
        if speed <= 0:
            raise GripperError(f"gripper speed must be > 0, got {speed}")
        self._grip_target_m = min(float(width_m), GRIPPER_MAX_WIDTH_M)
        self._grip_speed_mps = speed
        self._set_grip_effort(effort)

    # ------------------------------------------------------------------ stepping
    def _apply_controls(self) -> None:
        if self._noslip_hold != self._noslip_base:
            self._apply_noslip()
        self._ctrl[self._act_idx] = self._ref.command(self.data.time)
        if self._grip_cmd_m != self._grip_target_m:
            step = self._grip_speed_mps * self._opt.timestep
            diff = self._grip_target_m - self._grip_cmd_m
            self._grip_cmd_m = self._grip_target_m if abs(diff) <= step else self._grip_cmd_m + math.copysign(step, diff)
        self._ctrl[self._grip_act] = self._grip_cmd_m

    def _apply_noslip(self) -> None:
        """``noslip_hold_iterations`` no-slip passes while the hand holds an object by force
        (the fingers commanded shut and still apart on it), ``noslip_iterations`` otherwise:
        MuJoCo's soft contacts let a squeezed object creep between the pads under its weight;
        the passes make the pads' friction hold as Coulomb friction does."""
        holding = self._grip_target_m == 0.0 and self.finger_gap_m > _HOLDING_MIN_GAP_M
        passes = self._noslip_hold if holding else self._noslip_base
        if passes != self._noslip_now:
            self._opt.noslip_iterations = self._noslip_now = passes

    def step(self, n: int = 1) -> None:
        """Advance the physics by ``n`` steps, updating the controls before each.

        When frame listeners are registered (:meth:`add_frame_listener`) and frames are
        wanted (:attr:`frames_requested`), a depth frame is captured whenever one is due at
        the camera rate and handed to each listener, so whoever steps the world (an
        executor, a gripper wait) keeps perception fed while someone looks — the camera
        behaves like a sensor publishing at its rate on request.
        """
        m, d = self.model, self.data
        for _ in range(n):
            self._apply_controls()
            mujoco.mj_step(m, d)
            if self._frame_requests:
                self._looking_time_s += m.opt.timestep
            elif not self._continuous_frames:
                continue
            if self._frame_listeners:
                frame = self.poll_frame()
                if frame is not None:
                    for listener in list(self._frame_listeners):
                        listener(frame)

    # ------------------------------------------------------------------ frames on demand
    @contextmanager
    def request_frames(self) -> Iterator[None]:
        """Frames are wanted while this context is open (counted: requests nest). The first
        frame is captured at the next step (never sooner than one camera period after the
        previous frame), then one per period, until the last request closes."""
        self._frame_requests += 1
        try:
            yield
        finally:
            self._frame_requests -= 1

    @property
    def frames_requested(self) -> bool:
        """True when stepping delivers frames (continuous mode, or a request is open)."""
        return self._continuous_frames or self._frame_requests > 0

    @property
    def looking_time_s(self) -> float:
        """The looking clock [s]: simulated time during which frames were requested (in
        continuous mode: all simulated time). Perception liveness is judged on it: a dead
        camera is one that delivers nothing while someone looks."""
        return self.time_s if self._continuous_frames else self._looking_time_s

    def add_frame_listener(self, listener: Callable[[Frame], None]) -> None:
        """Call ``listener(frame)`` for every frame due while the world is stepped and
        frames are requested (:meth:`request_frames`; always in continuous mode)."""
        if self.camera is None:
            raise ModelError("this SimWorld was created with camera=False: no frames to listen to")
        self._frame_listeners.append(listener)

    def remove_frame_listener(self, listener: Callable[[Frame], None]) -> None:
        if listener in self._frame_listeners:
            self._frame_listeners.remove(listener)

    def run_until(self, until: float | Callable[["SimWorld"], bool], *,
                  max_duration_s: float | None = None,
                  on_frame: Callable[[Frame], None] | None = None) -> bool:
        """Step until a time or a condition (blocking).

        Args:
            until: an absolute simulated time [s], or a predicate ``f(world) -> bool`` tested
                after every step.
            max_duration_s: give up after this much simulated time (required with a predicate
                unless you are sure it becomes true).
            on_frame: if given, depth frames are requested and captured at the camera rate
                (simulated time) and passed to it.

        Returns True when the time was reached / the predicate became true, False on timeout.
        """
        t_limit = math.inf if max_duration_s is None else self.time_s + max_duration_s
        if callable(until):
            def done() -> bool:
                return bool(until(self))
        else:
            t_goal = float(until)

            def done() -> bool:
                return self.time_s >= t_goal - 0.5 * self.timestep_s
        if on_frame is None:
            return self._step_until(done, t_limit)
        self.add_frame_listener(on_frame)
        try:
            with self.request_frames():
                return self._step_until(done, t_limit)
        finally:
            self.remove_frame_listener(on_frame)

    def _step_until(self, done: Callable[[], bool], t_limit: float) -> bool:
        while not done():
            if self.time_s >= t_limit - 0.5 * self.timestep_s:
                return False
            self.step()
        return True

    # ------------------------------------------------------------------ camera
    def capture(self) -> Frame:
        """A depth frame of the current state; its pose and time are those of this instant."""
        if self.camera is None:
            raise ModelError("this SimWorld was created with camera=False")
        # After mj_step the kinematics in data are those of the previous state; bring them to
        # the current qpos so the image, the pose and time_s all describe the same instant.
        mujoco.mj_kinematics(self.model, self.data)
        mujoco.mj_camlight(self.model, self.data)
        return self.camera.capture()

    def poll_frame(self) -> Frame | None:
        """A frame if one is due at the camera rate (simulated time), else None."""
        if self.camera is None or self.time_s + 1e-9 < self._next_frame_time_s:
            return None
        period = self.camera_config.period_s
        self._next_frame_time_s += period
        if self._next_frame_time_s <= self.time_s:  # fell behind (e.g. after a long step)
            self._next_frame_time_s = self.time_s + period
        return self.capture()

    # ------------------------------------------------------------------ contacts
    def geom_name(self, geom_id: int) -> str:
        if self._geom_names is None:  # (names are fixed once the model is compiled)
            self._geom_names = [self.model.geom(i).name or f"geom{i}" for i in range(self.model.ngeom)]
        return self._geom_names[geom_id]

    def is_robot_geom(self, geom_id: int) -> bool:
        return bool(self._robot_geom[geom_id])

    def _contact_key(self) -> bytes:
        """The geom pairs of the active contacts in contact order, as bytes: equal keys mean
        the same contacts (what is touching what), so answers derived from them can be kept
        while the key stays the same (a scene at rest, a held object: for many steps)."""
        d = self.data
        return d.contact.geom.tobytes() if d.ncon else b""

    def _robot_pairs(self) -> np.ndarray | None:
        """(k, 2) geom ids (robot geom, other geom) of the contacts between a robot geom and a
        non-robot geom, in contact order; None when there is none. Vectorised: most contacts
        are object-table contacts."""
        d = self.data
        if d.ncon == 0:
            return None
        pairs = d.contact.geom
        robot = self._robot_geom[pairs]
        if not np.count_nonzero(robot):  # (the usual case: the robot touches nothing)
            return None
        mixed = robot[:, 0] != robot[:, 1]
        if not mixed.any():
            return None
        out = pairs[mixed]
        swap = ~robot[mixed, 0]
        out[swap] = out[swap][:, ::-1]
        return out

    def _named_robot_contacts(self, key: bytes) -> list[tuple[str, str]]:
        """:meth:`robot_contacts` (objects included) of the contacts whose key is ``key`` (the
        current one), kept until the contacts change (called at every monitored step)."""
        if key != self._contacts_memo[0]:
            pairs = self._robot_pairs()
            name = self.geom_name
            named = [] if pairs is None else [(name(r), name(o)) for r, o in pairs.tolist()]
            self._contacts_memo = (key, named)
        return self._contacts_memo[1]

    def robot_contacts(self, include_objects: bool = True) -> list[tuple[str, str]]:
        """Active contacts between robot geoms and non-robot geoms, as
        ``(robot_geom_name, other_geom_name)`` pairs (one entry per contact point).

        ``include_objects=False`` leaves out contacts with the graspable objects (``obj_*``),
        i.e. lists only robot-environment contacts (table, floor, wall, tray).
        """
        out = self._named_robot_contacts(self._contact_key())
        return list(out) if include_objects else [(r, o) for r, o in out
                                                  if not o.startswith(OBJECT_PREFIX)]

    def unexpected_contacts(self, allowance: ContactAllowance) -> list[str]:
        """The contact monitor (:class:`~grasp_pipeline.robot.protocols.ContactMonitor`):
        robot contacts that ``allowance`` does not cover, as ``"robot_geom-other_geom"``.

        ``FINGERS``: finger geoms touching objects are expected. ``HELD_OBJECT``: the objects
        the finger pads touch now (any of their collision parts) may touch any robot geom (a
        held object tilting against the palm). Fixtures (table, tray, wall) are never expected.
        (Called at every monitored physics step: the answer is kept while the contacts stay
        the same, :meth:`_contact_key`.)"""
        key = self._contact_key()
        memo = self._unexpected_memo
        if memo[0] is not allowance or memo[1] != key:
            memo = (allowance, key, _unexpected(self._named_robot_contacts(key), allowance))
            self._unexpected_memo = memo
        return list(memo[2])

    @property
    def work_cell(self) -> WorkCell:
        """The table top, the tray's boxes and the tray centre, read from the model."""
        return read_work_cell(self.model, self.data)


def _unexpected(contacts: list[tuple[str, str]], allowance: ContactAllowance) -> list[str]:
    """The robot contacts (robot geom, other geom) that ``allowance`` does not cover, as
    ``"robot_geom-other_geom"`` (see :meth:`SimWorld.unexpected_contacts`)."""
    if allowance is ContactAllowance.NONE:
        return [f"{r}-{o}" for r, o in contacts]
    if allowance is ContactAllowance.FINGERS:
        ok = {(r, o) for r, o in contacts if FINGER_GEOM_MARK in r and o.startswith(OBJECT_PREFIX)}
    else:
        held = {geom_object(o) for r, o in contacts
                if FINGER_GEOM_MARK in r and o.startswith(OBJECT_PREFIX)}
        ok = {(r, o) for r, o in contacts if geom_object(o) in held}
    return [f"{r}-{o}" for r, o in contacts if (r, o) not in ok]
