"""Simulator speed: real-time factors with and without the 640x480 depth camera, and the
pick loop's.

The arm follows a smooth joint trajectory (a slow sinusoid around the ready pose, velocities
included) in the reference scene for ``seconds`` of simulated time, twice:

* physics only (no frames): ``physics_real_time_factor`` = simulated / wall-clock seconds;
* with the depth camera capturing at its rate (30 Hz simulated): ``real_time_factor``.

Then, unless ``pick_scene`` is None, one pick-loop round (:mod:`.pick_loop_bench`: a
``run --declutter`` of ``pick_scene`` / ``pick_seed`` / ``pick_objects``, by default packed
seed 3 of the built-in objects) with its simulated seconds per CPU second and the CPU
breakdown physics / render / perception / planning / control / other (``pick_loop``).

Targets: physics >= 20x real time, with the camera >= 1x, on one core. The camera's
backend (egl / osmesa / raycast) is part of the result.

Both factors are wall-clock based; ``*cpu_real_time_factor`` divide by the process's CPU time
instead (all threads), i.e. what one otherwise idle core would achieve — the honest figure on
a machine shared with other work, where wall-clock factors drop with the load.
"""

from __future__ import annotations

import logging
import os
import platform
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

import numpy as np

from ..app.sim_system import SECTIONS
from ..report.serialize import write_json
from ..settings import load_settings
from ..sim.config import load_sim_config
from ..robot.description import READY_Q
from ..sim.world import SimWorld
from .pick_loop_bench import PickLoopResult, run_pick_loop

log = logging.getLogger(__name__)

PHYSICS_RTF_TARGET = 20.0
CAMERA_RTF_TARGET = 1.0
#: The benchmark motion: amplitude [rad] and period [s] of each joint's sinusoid.
MOTION_AMPLITUDE_RAD = np.array([0.4, 0.25, 0.3, 0.3, 0.4, 0.3, 0.5])
MOTION_PERIOD_S = 4.0
MOTION_SAMPLES_PER_S = 50
#: The pick-loop round: a packed scene of the built-in objects, cleared (``run --declutter``).
PICK_SCENE = "packed"
PICK_SEED = 3
PICK_OBJECTS = "builtin"


@dataclass(frozen=True)
class SimPass:
    """One pass of the benchmark motion: simulated, wall-clock and CPU seconds, their ratios,
    the camera's frames and backend (None: no camera), how well the arm followed."""

    sim_seconds: float
    wall_seconds: float
    cpu_seconds: float
    real_time_factor: float
    cpu_real_time_factor: float
    frames: int
    backend: Optional[str]
    final_tracking_error_rad: float


@dataclass(frozen=True)
class SimTargets:
    physics_real_time_factor: float = PHYSICS_RTF_TARGET
    real_time_factor: float = CAMERA_RTF_TARGET


@dataclass(frozen=True)
class SimMachine:
    python: str
    cpu_count: Optional[int]
    MUJOCO_GL: str  # noqa: N815  (the variable's name, as the JSON has it)


@dataclass(frozen=True, kw_only=True)
class SimBenchResult:
    """Real-time factors (simulated / wall-clock seconds; ``cpu_*``: / CPU seconds) of physics
    alone and with the camera, over ``seconds`` simulated seconds, and the pick loop's
    (None without it)."""

    seconds: float
    physics_real_time_factor: float
    real_time_factor: float
    physics_cpu_real_time_factor: float
    cpu_real_time_factor: float
    camera_backend: Optional[str]
    frames: int
    timestep_s: float
    targets: SimTargets = SimTargets()
    meets_targets: bool
    physics_pass: SimPass
    camera_pass: SimPass
    pick_loop: Optional[PickLoopResult]
    machine: SimMachine


def _benchmark_trajectory(seconds: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    t = np.linspace(0.0, seconds, max(2, int(seconds * MOTION_SAMPLES_PER_S) + 1))
    w = 2 * np.pi / MOTION_PERIOD_S
    s = np.sin(w * t)[:, None]
    q = READY_Q + MOTION_AMPLITUDE_RAD * s
    qd = MOTION_AMPLITUDE_RAD * w * np.cos(w * t)[:, None]
    return t, q, qd


def _run(seconds: float, camera: bool) -> SimPass:
    world = SimWorld(camera=camera)
    try:
        t, q, qd = _benchmark_trajectory(seconds)
        world.follow_trajectory(t, q, qd)
        frames = []
        on_frame = frames.append if camera else None
        wall0, cpu0 = time.perf_counter(), time.process_time()
        world.run_until(seconds, on_frame=on_frame)
        wall = time.perf_counter() - wall0
        cpu = time.process_time() - cpu0
        q_ref, _ = world.reference()
        return SimPass(sim_seconds=world.time_s, wall_seconds=wall, cpu_seconds=cpu,
                       real_time_factor=world.time_s / wall, cpu_real_time_factor=world.time_s / cpu,
                       frames=len(frames), backend=world.camera.backend if world.camera is not None else None,
                       final_tracking_error_rad=float(np.abs(world.q - q_ref).max()))
    finally:
        world.close()


def run_sim_benchmark(seconds: float, json_path: str | Path | None, pick_scene: str | None = PICK_SCENE,
                      pick_seed: int = PICK_SEED, pick_objects: str = PICK_OBJECTS,
                      overrides: tuple = (None, ())) -> SimBenchResult:
    """Run both passes and the pick loop (``pick_scene`` None: without it; ``overrides``:
    ``(config_file, [name=value, ...])`` for its settings), write the JSON (if ``json_path``)
    and return the result."""
    settings = None
    if pick_scene is not None:  # bad settings fail before anything runs
        settings = load_settings(SECTIONS, overrides[0], list(overrides[1]))
    physics = _run(seconds, camera=False)
    with_cam = _run(seconds, camera=True)
    pick_loop = None if settings is None else run_pick_loop(pick_scene, pick_seed, pick_objects, settings)
    result = SimBenchResult(
        seconds=seconds, physics_real_time_factor=physics.real_time_factor,
        real_time_factor=with_cam.real_time_factor, physics_cpu_real_time_factor=physics.cpu_real_time_factor,
        cpu_real_time_factor=with_cam.cpu_real_time_factor, camera_backend=with_cam.backend,
        frames=with_cam.frames, timestep_s=load_sim_config().timestep_s,
        meets_targets=bool(physics.real_time_factor >= PHYSICS_RTF_TARGET
                           and with_cam.real_time_factor >= CAMERA_RTF_TARGET),
        physics_pass=physics, camera_pass=with_cam, pick_loop=pick_loop,
        machine=SimMachine(python=platform.python_version(), cpu_count=os.cpu_count(),
                           MUJOCO_GL=os.environ.get("MUJOCO_GL", "")))
    if json_path is not None:
        Path(json_path).parent.mkdir(parents=True, exist_ok=True)
        write_json(json_path, result, sort_keys=True)
    _log_result(result, pick_scene, pick_seed)
    return result


def _log_result(result: SimBenchResult, pick_scene: Optional[str], pick_seed: int) -> None:
    log.info("sim benchmark: physics %.1fx real time, with %s camera %.2fx (%d frames)",
             result.physics_real_time_factor, result.camera_backend, result.real_time_factor, result.frames)
    if result.pick_loop is not None:
        log.info("pick loop (%s seed %d): %.1f simulated s per CPU s; CPU shares %s", pick_scene, pick_seed,
                 result.pick_loop.cpu_real_time_factor,
                 ", ".join(f"{k} {100 * v:.0f} %" for k, v in result.pick_loop.breakdown_share.items()))
