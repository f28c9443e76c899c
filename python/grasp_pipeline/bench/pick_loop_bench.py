"""The pick loop's speed: simulated seconds per CPU second of one ``run --declutter`` round and
where its CPU time goes.

One round (rough view, active scan, then picks until the table is clear or nothing more is
proposed; no video) runs in this process with :class:`~.cpu_accounts.CpuAccounts` on:

* ``physics`` — ``mujoco.mj_step``;
* ``render`` — the eye-in-hand frames (``SimWorld.capture``: kinematics, render, noise, points);
* ``perception`` — the frame listener of the perception loop (the C++ core, tracking, selection,
  the scene volume);
* ``planning`` — every public call of the motion planner (planning world updates, IK, OMPL,
  straight lines, TOPP-RA) and the grasp source's proposals;
* ``control`` — the world's per-step work around the physics (servo commands, frame polling)
  and the motion monitor's reads (reference, contacts);
* ``other`` — the rest: the runtime's task stepping, grasp and place logic, the tray model,
  scoring, snapshots, model building.

The accounts are exclusive and add up to the round's CPU time. Each accounted call costs two
clock reads; ``accounting_cpu_s`` estimates what they added (it sits in the accounts that
made the calls), so the factor is slightly pessimistic.
"""

from __future__ import annotations

import inspect
import tempfile
import time
import types
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Optional

import mujoco

from .cpu_accounts import OTHER, CpuAccounts

if TYPE_CHECKING:
    from ..settings import Settings

ACCOUNTS = ("physics", "render", "perception", "planning", "control", OTHER)


@dataclass(frozen=True, kw_only=True)
class PickLoopResult:
    """One declutter round's speed: simulated seconds per CPU (and wall) second and where the
    CPU time went (``breakdown_cpu_s`` by account, adding up to ``cpu_seconds``)."""

    scene: str
    seed: int
    objects: str
    status: str
    error: Optional[str]
    picks: int
    picked: int
    sim_seconds: float
    cpu_seconds: float
    wall_seconds: float
    cpu_real_time_factor: float
    real_time_factor: float
    physics_steps: int
    breakdown_cpu_s: dict[str, float]
    breakdown_share: dict[str, float]
    accounting_cpu_s: float


def _public_methods(obj: Any) -> list[str]:
    """Names of the public methods of ``obj``'s class (functions only: no properties)."""
    cls = type(obj)
    return [n for n in dir(cls) if not n.startswith("_")
            and isinstance(inspect.getattr_static(cls, n), types.FunctionType)]


def _account_system(acc: CpuAccounts, system: Any) -> None:
    """Wrap the calls of each account in a built system (``app.sim_system.System``)."""
    world = system.world
    acc.wrap(mujoco, "mj_step", "physics")
    acc.wrap(world, "capture", "render")
    acc.wrap(system.loop, "on_frame", "perception")
    for name in ("step", "reference", "unexpected_contacts"):
        acc.wrap(world, name, "control")
    planner = system.motion.planner
    for name in _public_methods(planner):
        acc.wrap(planner, name, "planning")


def _clock_pair_cpu_s(n: int = 2000) -> float:
    """CPU cost of one accounted call's two clock reads (measured here, now)."""
    t0 = time.process_time()
    for _ in range(n):
        time.process_time()
        time.process_time()
    return (time.process_time() - t0) / n


def run_pick_loop(scene: str, seed: int, objects: str, settings: "Settings") -> PickLoopResult:
    """One declutter round of ``scene`` / ``seed`` / ``objects`` with ``settings``
    (``grasp_pipeline.settings.Settings`` of ``app.sim_system.SECTIONS``); returns the figures."""
    from ..app.run import default_grasp_source, run_pipeline

    source = default_grasp_source(settings)
    acc = CpuAccounts()
    wall0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="bench_sim_") as out, acc.measure():
        acc.wrap(source, "propose", "planning")
        report = run_pipeline(scene, seed, out_dir=out, settings=settings, video=False,
                              grasp_source=source, objects=objects, declutter=True,
                              prepare=lambda system: _account_system(acc, system), mark_output=False)
    wall = time.perf_counter() - wall0
    sim_s = float(report.timings.get("run_sim_s", 0.0))
    cpu = acc.total_s
    seconds = {k: acc.seconds.get(k, 0.0) for k in ACCOUNTS}
    return PickLoopResult(
        scene=scene, seed=seed, objects=objects, status=report.status, error=report.error,
        picks=len(report.picks), picked=sum(1 for p in report.picks if p.success),
        sim_seconds=sim_s, cpu_seconds=cpu, wall_seconds=wall,
        cpu_real_time_factor=sim_s / cpu if cpu > 0 else 0.0,
        real_time_factor=sim_s / wall if wall > 0 else 0.0,
        physics_steps=acc.calls.get("physics", 0), breakdown_cpu_s=seconds,
        breakdown_share={k: (v / cpu if cpu > 0 else 0.0) for k, v in seconds.items()},
        accounting_cpu_s=sum(acc.calls.values()) * _clock_pair_cpu_s())
