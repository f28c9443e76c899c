"""Pretend hardware for the example: a Panda arm, a parallel gripper and a RealSense-like depth
camera on the hand, looking at boxes on a table.

Its interfaces look like vendor drivers' on purpose — joints read and commanded through the arm
driver, the gripper commanded by width and force, the camera returning raw uint16 depth in
millimetres with a depth scale and intrinsics as fx, fy, ppx, ppy — so that ``adapter.py`` shows
the conversions a real adapter makes. It is not a simulator: there is no physics. The arm
follows its commanded trajectory exactly, a box between closing fingers stops them and then
follows the hand, and a released box drops onto whatever is under it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

import mujoco

from grasp_pipeline.robot.description import arm_qpos_indices, flange_pose, flange_T_tcp, load_robot_model


@dataclass
class ToyBox:
    """A box: centre (3,) [m], rotation (3, 3) (columns: its axes in the world), full sizes (3,) [m]."""

    name: str
    center: np.ndarray
    R: np.ndarray
    size: np.ndarray
    movable: bool = False

    @classmethod
    def upright(cls, name: str, center, size, yaw_deg: float = 0.0, movable: bool = False) -> "ToyBox":
        c, s = np.cos(np.radians(yaw_deg)), np.sin(np.radians(yaw_deg))
        R = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        return cls(name, np.asarray(center, float), R, np.asarray(size, float), movable)

    def contains(self, p: np.ndarray, margin_m: float = 0.0) -> bool:
        local = self.R.T @ (np.asarray(p, float) - self.center)
        return bool(np.all(np.abs(local) <= 0.5 * self.size + margin_m))

    def width_along(self, axis: np.ndarray) -> float:
        """The box's extent along the unit vector ``axis`` [m]."""
        return float(np.abs(self.R.T @ axis) @ self.size)


class ToyArmDriver:
    """Joint position control of a 7-joint arm that follows a timed trajectory exactly."""

    def __init__(self, q0: np.ndarray) -> None:
        self._t, self._q = np.zeros(1), np.asarray(q0, float).reshape(1, 7).copy()
        self.q, self.qd = self._q[0].copy(), np.zeros(7)

    def start_trajectory(self, t_abs: np.ndarray, q: np.ndarray) -> None:
        self._t, self._q = np.asarray(t_abs, float), np.asarray(q, float)

    def stop(self, q: Optional[np.ndarray] = None) -> None:
        """Hold ``q`` (default: where the arm is)."""
        self.start_trajectory(np.zeros(1), (self.q if q is None else np.asarray(q, float)).reshape(1, 7))

    def target(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        """The commanded joints and velocities at time ``t`` (linear between samples)."""
        tt, qq = self._t, self._q
        if len(tt) == 1 or t <= tt[0]:
            return qq[0].copy(), np.zeros(7)
        if t >= tt[-1]:
            return qq[-1].copy(), np.zeros(7)
        k = int(np.searchsorted(tt, t)) - 1
        a = (t - tt[k]) / (tt[k + 1] - tt[k])
        return qq[k] + a * (qq[k + 1] - qq[k]), (qq[k + 1] - qq[k]) / (tt[k + 1] - tt[k])

    def update(self, t: float) -> None:
        self.q, self.qd = self.target(t)


class ToyGripperDriver:
    """Coupled fingers: the gap moves to the commanded width at ``speed_mps``; closing on a box
    stalls at its width and squeezes with the commanded force."""

    MAX_WIDTH_M = 0.08

    def __init__(self, speed_mps: float = 0.1) -> None:
        self.width_m, self.speed_mps, self.force_N = self.MAX_WIDTH_M, speed_mps, 0.0
        self.finger_speed_mps = 0.0
        self._cmd_m, self._force_cmd_N = self.MAX_WIDTH_M, 40.0

    def command(self, width_m: float, force_N: float) -> None:
        self._cmd_m, self._force_cmd_N = float(np.clip(width_m, 0.0, self.MAX_WIDTH_M)), float(force_N)

    def update(self, dt: float, object_width_m: Optional[float]) -> None:
        target = self._cmd_m
        blocked = object_width_m is not None and target < object_width_m <= self.width_m + 1e-9
        if blocked:
            target = object_width_m
        move = float(np.clip(target - self.width_m, -self.speed_mps * dt, self.speed_mps * dt))
        self.width_m += move
        self.finger_speed_mps = 0.5 * move / dt
        self.force_N = self._force_cmd_N if blocked and abs(self.width_m - object_width_m) < 1e-9 else 0.0


class ToyDepthCamera:
    """A RealSense-D435-like depth stream at 424x240: raw uint16 depth in units of
    :attr:`depth_scale` metres (0: no return), 1 mm quantisation, seeded noise."""

    def __init__(self, width: int = 424, height: int = 240, f_px: float = 216.0, seed: int = 0,
                 noise_m: float = 0.001, min_range_m: float = 0.12, max_range_m: float = 3.0) -> None:
        self.width, self.height = width, height
        self.fx = self.fy = f_px
        self.ppx, self.ppy = 0.5 * (width - 1), 0.5 * (height - 1)
        self.depth_scale = 0.001
        self.noise_m, self.min_range_m, self.max_range_m = noise_m, min_range_m, max_range_m
        self._rng = np.random.default_rng(seed)
        u = (np.arange(width) - self.ppx) / self.fx
        v = (np.arange(height) - self.ppy) / self.fy
        self._rays = np.stack(np.broadcast_arrays(u[None, :], v[:, None], 1.0), axis=-1).reshape(-1, 3)
        self._rays = self._rays.astype(np.float32)

    def capture(self, T_world_camera: np.ndarray, boxes: list[ToyBox]) -> np.ndarray:
        """(H, W) uint16 raw depth of ``boxes`` and the floor seen from ``T_world_camera``."""
        R, o = T_world_camera[:3, :3], T_world_camera[:3, 3]
        d = self._rays @ R.T.astype(np.float32)  # ray directions in the world, scaled so that camera z = 1
        with np.errstate(divide="ignore", invalid="ignore"):
            z = np.where(d[:, 2] < 0, np.float32(-o[2]) / d[:, 2], np.float32(np.inf))  # the floor, z = 0
        for box in boxes:
            np.minimum(z, self._hit(box, o, d, T_world_camera), out=z)
        z += self._rng.standard_normal(z.shape, dtype=np.float32) * np.float32(self.noise_m)
        ok = np.isfinite(z) & (z >= self.min_range_m) & (z <= self.max_range_m)
        raw = np.where(ok, np.round(np.where(ok, z, 0.0) / self.depth_scale), 0)
        return raw.astype(np.uint16).reshape(self.height, self.width)

    def _hit(self, box: ToyBox, o: np.ndarray, d: np.ndarray, T: np.ndarray) -> np.ndarray:
        """Depth (camera z) where each ray enters ``box`` (inf: it misses); only the rays in
        the image rectangle of the box's corners are cast (slab test, one axis at a time)."""
        z = np.full(len(d), np.inf, dtype=np.float32)
        idx = self._rays_near(box, T)
        ol, dl = box.R.T @ (o - box.center), d[idx] @ box.R.astype(np.float32)
        near = np.zeros(len(idx), dtype=np.float32)  # rays start at the camera
        far = np.full(len(idx), np.inf, dtype=np.float32)
        with np.errstate(divide="ignore", invalid="ignore"):
            for a in range(3):
                inv = np.float32(1.0) / dl[:, a]
                t1 = (np.float32(-0.5 * box.size[a] - ol[a])) * inv
                t2 = (np.float32(0.5 * box.size[a] - ol[a])) * inv
                np.maximum(near, np.fmin(t1, t2), out=near)
                np.minimum(far, np.fmax(t1, t2), out=far)
        hit = near <= far
        z[idx[hit]] = near[hit]
        return z

    def _rays_near(self, box: ToyBox, T: np.ndarray) -> np.ndarray:
        corners = box.center + (np.array(np.meshgrid(*[[-0.5, 0.5]] * 3)).reshape(3, -1).T * box.size) @ box.R.T
        cam = (corners - T[:3, 3]) @ T[:3, :3]
        if np.any(cam[:, 2] <= 1e-3):  # partly behind the camera: cast every ray
            return np.arange(len(self._rays))
        u, v = self.fx * cam[:, 0] / cam[:, 2] + self.ppx, self.fy * cam[:, 1] / cam[:, 2] + self.ppy
        u0, u1 = np.clip([np.floor(u.min()), np.ceil(u.max())], 0, self.width - 1).astype(int)
        v0, v1 = np.clip([np.floor(v.min()), np.ceil(v.max())], 0, self.height - 1).astype(int)
        if u.max() < 0 or v.max() < 0 or u.min() > self.width - 1 or v.min() > self.height - 1:
            return np.zeros(0, dtype=int)
        cols, rows = np.meshgrid(np.arange(u0, u1 + 1), np.arange(v0, v1 + 1))
        return (rows * self.width + cols).ravel()


class ToyHardware:
    """The pretend cell: arm, gripper, camera on the hand (mounted at ``flange_T_camera``) and
    the boxes (fixed ones: table, tray; movable ones: the objects). :meth:`tick` advances it."""

    def __init__(self, q0: np.ndarray, boxes: list[ToyBox], flange_T_camera: np.ndarray) -> None:
        self.time_s = 0.0
        self.arm, self.gripper, self.camera = ToyArmDriver(q0), ToyGripperDriver(), ToyDepthCamera()
        self.boxes = list(boxes)
        self._mount = np.asarray(flange_T_camera, float)
        self._model = load_robot_model()  # the Panda's kinematics (MuJoCo as a kinematics library)
        self._data = mujoco.MjData(self._model)
        self._arm_qpos = arm_qpos_indices(self._model)
        self._tcp_in_flange = flange_T_tcp(self._model)
        self.held: Optional[tuple[ToyBox, np.ndarray, float]] = None  # box, its pose in the TCP, width

    def flange_pose(self) -> np.ndarray:
        """Forward kinematics of the joints now (a real arm reports it, e.g. libfranka's O_T_EE)."""
        self._data.qpos[self._arm_qpos] = self.arm.q
        mujoco.mj_kinematics(self._model, self._data)
        return flange_pose(self._model, self._data)

    def tcp_pose(self) -> np.ndarray:
        return self.flange_pose() @ self._tcp_in_flange

    def camera_image(self) -> np.ndarray:
        return self.camera.capture(self.flange_pose() @ self._mount, self.boxes)

    def tick(self, dt: float) -> None:
        self.time_s += dt
        self.arm.update(self.time_s)
        T_tcp = self.tcp_pose()
        if self.held is not None:
            box, T_tcp_box, width = self.held
            self.gripper.update(dt, width)
            if self.gripper.width_m > width + 0.002:  # opened: the box falls
                self.held = None
                self._drop(box)
            else:  # held: it follows the hand
                T = T_tcp @ T_tcp_box
                box.center, box.R = T[:3, 3].copy(), T[:3, :3].copy()
            return
        found = self._box_between(T_tcp)
        self.gripper.update(dt, None if found is None else found[1])
        if found is not None and self.gripper.force_N > 0:  # the fingers squeeze it: grasped
            self.held = (found[0], np.linalg.inv(T_tcp) @ _pose(found[0]), found[1])

    def _box_between(self, T_tcp: np.ndarray) -> Optional[tuple[ToyBox, float]]:
        """The movable box the TCP is inside of, with its width along the closing axis."""
        for box in self.boxes:
            if box.movable and box.contains(T_tcp[:3, 3]):
                return box, box.width_along(T_tcp[:3, 1])
        return None

    def _drop(self, box: ToyBox) -> None:
        """A released box falls upright (keeping its yaw) onto the highest surface under it."""
        yaw = np.arctan2(box.R[1, 0], box.R[0, 0])
        height = box.width_along(np.array([0.0, 0.0, 1.0]))
        below = [b for b in self.boxes if b is not box and b.contains(
            np.r_[box.center[:2], b.center[2]], margin_m=0.0)]
        floor = max((b.center[2] + 0.5 * b.width_along(np.array([0.0, 0.0, 1.0])) for b in below
                     if b.center[2] < box.center[2]), default=0.0)
        dropped = ToyBox.upright(box.name, [box.center[0], box.center[1], floor + 0.5 * height],
                                 [box.width_along(np.array([np.cos(yaw), np.sin(yaw), 0.0])),
                                  box.width_along(np.array([-np.sin(yaw), np.cos(yaw), 0.0])), height],
                                 np.degrees(yaw), movable=True)
        box.center, box.R, box.size = dropped.center, dropped.R, dropped.size


def _pose(box: ToyBox) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = box.R, box.center
    return T
