"""Planning benchmark: success and speed of the motion layer on random scenes, executed in the sim.

For each of N seeded random scenes (``grasp_pipeline.sim.scenes.random_scene``):

1. the scene is perceived once from the start pose (:func:`perceive_scene`; obstacles =
   perceived environment points + object boxes, never ground truth);
2. the scan motions: start → camera above object 1 → … → camera above object K → start
   (SPEC 3 camera-above pose, planned to the flange pose);
3. for every perceived object: start → pre-grasp (``pregrasp_offset_m`` above the grasp) →
   straight approach to the grasp (target box may be entered by the hand) → straight lift
   (``lift_height_m``) → start. The gripper stays open (no grasping here: this measures the
   motions).

Every motion is planned, timed (TOPP-RA) and executed with the monitoring executor. Robot
contacts with the environment or with non-target objects during execution are counted
(``robot_contacts_during_motion``); the target's own geoms are expected contacts during the
approach/lift only. Matching a perceived box to a simulated object (to know which geom is the
target) uses ground truth — allowed here because this is scoring code, never planning input.

Figures: ``plans`` (count), ``success_rate`` (planned *and* executed without a stop),
``median_ms`` / ``p90_ms`` of the planning wall time (IK + collision checks + OMPL, without
timing), ``toppra_median_ms``, per-kind breakdowns, ``robot_contacts_during_motion``.
"""

from __future__ import annotations

import argparse
import json
from dataclasses import dataclass
import logging
import time
from pathlib import Path

import numpy as np

log = logging.getLogger(__name__)

#: The open gripper must exceed the object's width by at least this much [m].
GRIPPER_CLEARANCE_M = 0.01


def _median(x: list[float]) -> float:
    return float(np.median(x)) if x else float("nan")


def _p90(x: list[float]) -> float:
    return float(np.percentile(x, 90)) if x else float("nan")


@dataclass(frozen=True)
class _Perceived:
    environment_points: np.ndarray
    object_boxes: list
    capture_q: np.ndarray
    T_world_camera: np.ndarray
    plane: object


def perceive_scene(world) -> _Perceived:
    """The scene as the perception core sees it in one frame from the current pose."""
    from ..motion.occupancy import OrientedBox
    from ..perception import PerceptionSession

    frame = world.capture()
    session = PerceptionSession()
    res = session.process(frame.points_world, frame.T_world_camera[:3, 3], frame.time_s)
    if res.table is None:
        raise RuntimeError("perception found no table plane from the start pose")
    boxes = [OrientedBox(np.asarray(e.center), np.asarray(e.R_box), np.asarray(e.extents))
             for e in res.estimates]
    return _Perceived(np.asarray(res.environment_points(), dtype=float), boxes,
                      np.asarray(world.q, dtype=float).copy(), frame.T_world_camera.copy(), res.table)


def run_planning_benchmark(scenes: int, seed: int, json_path: str | Path | None) -> dict:
    """Run the benchmark on ``scenes`` random scenes starting at ``seed``; write JSON."""
    from ..motion.executor import TrajectoryExecutor
    from ..motion.exceptions import ExecutionError, MotionError
    from ..motion.grasp_poses import offset_along, top_down_grasp_tcp
    from ..motion.motion_planner import MotionPlanner
    from .. import _core
    from ..sim import robot_model as rm
    from ..sim.ground_truth import object_truths
    from ..sim.scenes import random_scene
    from ..sim.world import SimWorld, object_body_name

    if scenes < 1:
        raise ValueError(f"scenes must be >= 1, got {scenes}")
    mp = MotionPlanner()
    cfg = mp.config
    flange_T_cam = rm.flange_T_camera(mp.model)
    n_up = np.array([0.0, 0.0, 1.0])
    records: list[dict] = []
    contacts_total = 0
    contact_examples: list[str] = []
    t_wall = time.perf_counter()

    for k in range(scenes):
        scene = random_scene(seed + k)
        with SimWorld(scene) as world:
            start_q = world.q.copy()
            # plans start from the joints the arm was last commanded to (it holds them; the
            # measured joints differ by the servo's steady-state error, < settle tolerance)
            q_cmd = [start_q.copy()]
            perceived = perceive_scene(world)
            t_env = time.perf_counter()
            mp.set_scene(perceived.environment_points, perceived.object_boxes, capture_q=perceived.capture_q)
            env_ms = (time.perf_counter() - t_env) * 1e3
            ex = TrajectoryExecutor(world, cfg)
            truths = object_truths(world)

            def run(kind: str, plan_fn, allowed: tuple[str, ...] = (), allow_target: bool = False) -> bool:
                nonlocal contacts_total
                rec = {"scene": scene.name, "kind": kind, "ok": False}
                records.append(rec)
                try:
                    path = plan_fn()
                    rec.update(planning_ms=path.planning_ms, method=path.method, attempts=path.attempts)
                    traj = mp.time_path(path, allow_target)
                    rec.update(toppra_ms=traj.timing_ms, duration_s=traj.duration_s)
                except MotionError as exc:
                    rec["error"] = f"{type(exc).__name__}: {exc}"
                    log.warning("%s %s: %s", scene.name, kind, rec["error"])
                    return False
                try:
                    rep = ex.execute(traj, allowed_contact_prefixes=allowed)
                    rec.update(max_tracking_error_rad=rep.max_tracking_error_rad)
                    q_cmd[0] = traj.q[-1].copy()
                except ExecutionError as exc:
                    rec["error"] = f"ExecutionError({exc.reason}): {exc}"
                    if exc.reason == "contact":
                        contacts_total += 1
                        contact_examples.append(f"{scene.name} {kind}: {exc}")
                    log.warning("%s %s: %s", scene.name, kind, rec["error"])
                    world.hold()
                    q_cmd[0] = world.q.copy()
                    return False
                rec["ok"] = True
                return True

            def back_to_start(kind: str) -> bool:
                return run(kind, lambda: mp.plan_path_to_joints(q_cmd[0], start_q))

            # --- scan: start -> above each object -> start
            mp.set_target(None)
            for i, box in enumerate(mp.boxes):
                T_f = _core.camera_above_flange_target(
                    box.center, perceived.plane, _core.Pose.from_matrix(perceived.T_world_camera),
                    _core.Pose.from_matrix(flange_T_cam)).matrix()
                if not run("scan_probe", lambda T_f=T_f: mp.plan_path_to_pose(q_cmd[0], T_f, "flange")):
                    break
            back_to_start("scan_return")

            # --- grasp motions for every perceived object
            for i, box in enumerate(perceived.object_boxes):
                if np.max(np.abs(q_cmd[0] - start_q)) > cfg.settle_position_tol_rad * 10:
                    if not back_to_start("recover"):
                        break
                mp.set_target(i)
                nearest = min(truths, key=lambda t: np.linalg.norm(t.position_m[:2] - box.center[:2]))
                allowed = (object_body_name(nearest.name),)
                # closing axis: the narrower footprint axis first, the other if it fits too
                axes = [int(a) for a in np.argsort(box.extents[:2])
                        if box.extents[int(a)] <= rm.GRIPPER_MAX_WIDTH_M - GRIPPER_CLEARANCE_M]
                planned = None
                first_error = None
                t_try = time.perf_counter()
                for axis in axes or [int(np.argmin(box.extents[:2]))]:
                    T_grasp = top_down_grasp_tcp(box, n_up, mp.ik.fk_tcp(start_q), closing_axis=axis)
                    T_pre = offset_along(T_grasp, n_up, cfg.pregrasp_offset_m)
                    try:
                        p_pre = mp.plan_path_to_pose(q_cmd[0], T_pre, "tcp")
                        p_app = mp.plan_path_cartesian(p_pre.goal, T_grasp, "tcp", True)
                        planned = (T_grasp, p_pre, p_app)
                        break
                    except MotionError as exc:
                        first_error = first_error or exc
                if planned is None:
                    records.append({"scene": scene.name, "kind": "pregrasp+approach", "ok": False,
                                    "planning_ms": (time.perf_counter() - t_try) * 1e3,
                                    "method": "none", "attempts": 0,
                                    "error": f"{type(first_error).__name__}: {first_error}"})
                    log.warning("%s grasp %d: %s", scene.name, i, records[-1]["error"])
                    mp.set_target(None)
                    continue
                T_grasp, p_pre, p_app = planned
                T_lift = offset_along(T_grasp, n_up, cfg.lift_height_m)
                ok = run("pregrasp", lambda: p_pre)
                ok = ok and run("approach", lambda: p_app, allowed, True)
                ok = ok and run("lift", lambda: mp.plan_path_cartesian(q_cmd[0], T_lift, "tcp", True),
                                allowed, True)
                if ok:
                    mp.set_target(None)  # 10 cm above it now: the target is an obstacle again
                else:
                    T_pre = offset_along(T_grasp, n_up, cfg.pregrasp_offset_m)
                    run("retreat", lambda: mp.plan_path_cartesian(q_cmd[0], T_pre, "tcp", True),
                        allowed, True)
                back_to_start("grasp_return")
            mp.set_target(None)
        log.info("scene %d/%d (%s): %d objects perceived, env map %s in %.0f ms", k + 1, scenes,
                 scene.name, len(perceived.object_boxes), mp.env, env_ms)

    planned = [r for r in records if "planning_ms" in r]
    ms = [r["planning_ms"] for r in planned]
    tms = [r["toppra_ms"] for r in records if "toppra_ms" in r]
    by_kind = {}
    for kind in sorted({r["kind"] for r in records}):
        rs = [r for r in records if r["kind"] == kind]
        by_kind[kind] = {"plans": len(rs), "success_rate": sum(r["ok"] for r in rs) / len(rs),
                         "median_ms": _median([r["planning_ms"] for r in rs if "planning_ms" in r])}
    methods: dict[str, int] = {}
    for r in planned:
        methods[r["method"]] = methods.get(r["method"], 0) + 1
    result = {
        "scenes": scenes,
        "seed": seed,
        "plans": len(records),
        "successes": int(sum(r["ok"] for r in records)),
        "success_rate": (sum(r["ok"] for r in records) / len(records)) if records else 0.0,
        "median_ms": _median(ms),
        "p90_ms": _p90(ms),
        "max_ms": float(max(ms)) if ms else float("nan"),
        "toppra_median_ms": _median(tms),
        "toppra_p90_ms": _p90(tms),
        "robot_contacts_during_motion": contacts_total,
        "contact_examples": contact_examples[:20],
        "methods": methods,
        "by_kind": by_kind,
        "failures": [r for r in records if not r["ok"]][:50],
        "wall_time_s": time.perf_counter() - t_wall,
        "planner": cfg.planner,
        "perception": "C++ core: one frame from the start pose (scene filter + object estimates)",
    }
    if json_path is not None:
        p = Path(json_path)
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(json.dumps(result, indent=2, sort_keys=True))
    return result


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="motion-layer planning benchmark on random scenes")
    ap.add_argument("--scenes", type=int, default=50)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--json", type=Path, default=None)
    ap.add_argument("--log-level", default="WARNING")
    args = ap.parse_args(argv)
    logging.basicConfig(level=getattr(logging, args.log_level))
    logging.getLogger("toppra").setLevel(logging.WARNING)
    res = run_planning_benchmark(args.scenes, args.seed, args.json)
    summary = {k: v for k, v in res.items() if k not in ("failures", "contact_examples")}
    print(json.dumps(summary, indent=2, sort_keys=True))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
