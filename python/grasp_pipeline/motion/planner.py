"""Joint-space planning: straight line first, then OMPL (RRTConnect by default).

``JointPlanner.plan(q_start, q_goal)``:

1. validates the inputs; an invalid start or goal raises StartInCollisionError /
   GoalInCollisionError with the reason (limit, self-collision, environment, object box);
2. checks the straight joint-space line densely (≤ ``final_check_step_rad`` per joint,
   0.5°): if free, that *is* the plan (method ``"direct"``) — the common case, ~ms;
3. otherwise runs OMPL: up to ``num_planning_attempts`` runs within ``planning_time_s`` in
   total (both upper bounds: a run stops at its first exact solution). Edges are checked at
   ``planner_check_step_rad``; the solution is shortcut-simplified, then every segment is
   re-checked densely at ``final_check_step_rad``. If the simplified path fails that check
   the raw path is tried; if both fail, the next attempt runs.

The result's waypoints start exactly at ``q_start`` and end exactly at ``q_goal``.
"""

from __future__ import annotations

import logging
import time

import numpy as np

from .config import MotionConfig
from .exceptions import GoalInCollisionError, PlanningFailedError, StartInCollisionError
from .poses import validate_joints
from .state_space import (import_ompl, make_motion_validator, make_planner, make_space, make_state,
                          state_to_array, state_validity_checker)
from .trajectory import JointPath
from .validity import StateValidator

log = logging.getLogger(__name__)

_SEEDED = False


def reseed_next_planner() -> None:
    """Make the next :class:`JointPlanner` seed OMPL again, as in a fresh process: a worker
    process that runs one job after another calls this before each job, so that every job
    plans from the same random state as in a process of its own."""
    global _SEEDED
    _SEEDED = False


def _path(wp: np.ndarray, t0: float, c0: float, method: str, attempts: int, checked: int) -> JointPath:
    """The result with its wall time since ``t0`` (perf_counter) and thread CPU since ``c0``."""
    return JointPath(wp, (time.perf_counter() - t0) * 1e3, method, attempts, checked,
                     (time.thread_time() - c0) * 1e3)


def _seed_ompl(ou, seed: int) -> None:
    """Seed OMPL's generator of per-sampler seeds. Seeding it again (a worker's next job)
    restarts the same sequence; OMPL then logs an error meant for code that seeds mid-run, which
    does not apply here and is silenced. Seed 0 is passed as 1: OMPL seeds with 1 when first
    given 0, but ignores a later 0."""
    level = ou.getLogLevel()
    ou.setLogLevel(ou.LOG_NONE)
    try:
        ou.RNG.setSeed(seed or 1)
    finally:
        ou.setLogLevel(level)


class JointPlanner:
    """Plans collision-free joint paths for one :class:`StateValidator` (one scene)."""

    def __init__(self, validator: StateValidator, config: MotionConfig) -> None:
        self.validator = validator
        self.config = config
        global _SEEDED
        _, _, ou = import_ompl()
        if config.random_seed >= 0 and not _SEEDED:
            _seed_ompl(ou, int(config.random_seed))
            _SEEDED = True

    def plan(self, q_start: np.ndarray, q_goal: np.ndarray) -> JointPath:
        t0, c0 = time.perf_counter(), time.thread_time()
        cfg = self.config
        v = self.validator
        qs = validate_joints(q_start, "start joints")
        qg = validate_joints(q_goal, "goal joints")
        n0 = v.checked_states
        if not v.is_valid(qs):
            raise StartInCollisionError(f"start state is invalid: {v.explain(qs)}")
        if not v.is_valid(qg):
            raise GoalInCollisionError(f"goal state is invalid: {v.explain(qg)}")
        if np.max(np.abs(qg - qs)) < 1e-12:
            return _path(np.vstack([qs, qg]), t0, c0, "direct", 0, v.checked_states - n0)
        if cfg.try_direct_first and v.check_segment(qs, qg, cfg.final_check_step_rad):
            return _path(np.vstack([qs, qg]), t0, c0, "direct", 0, v.checked_states - n0)
        wp, attempts = self._plan_ompl(qs, qg, t0)
        return _path(wp, t0, c0, cfg.planner, attempts, v.checked_states - n0)

    def _plan_ompl(self, qs: np.ndarray, qg: np.ndarray, t0: float) -> tuple[np.ndarray, int]:
        ob, og, _ = import_ompl()
        cfg = self.config
        v = self.validator
        space = make_space(v.q_min, v.q_max)
        ss = og.SimpleSetup(space)
        ss.setStateValidityChecker(state_validity_checker(v))
        si = ss.getSpaceInformation()
        mv = make_motion_validator(si, v, cfg.planner_check_step_rad)
        si.setMotionValidator(mv)
        ss.setStartAndGoalStates(make_state(space, qs), make_state(space, qg))
        ss.setPlanner(make_planner(cfg.planner, si, cfg))
        ss.setup()
        statuses = []
        for attempt in range(1, cfg.num_planning_attempts + 1):
            remaining = cfg.planning_time_s - (time.perf_counter() - t0)
            if remaining <= 0:
                break
            if attempt > 1:
                ss.clear()
            ptc = ob.plannerOrTerminationCondition(
                ob.timedPlannerTerminationCondition(remaining),
                ob.exactSolnPlannerTerminationCondition(ss.getProblemDefinition()))
            status = ss.solve(ptc)
            statuses.append(str(status))
            if not ss.haveExactSolutionPath():
                continue
            raw = self._path_array(ss.getSolutionPath())
            ss.simplifySolution(cfg.simplify_max_time_s)
            simplified = self._path_array(ss.getSolutionPath())
            for wp in (simplified, raw):
                wp = wp.copy()
                wp[0], wp[-1] = qs, qg
                bad = v.check_path(wp, cfg.final_check_step_rad)
                if bad is None:
                    return wp, attempt
                log.debug("attempt %d: path segment %d fails the dense re-check", attempt, bad)
        elapsed = time.perf_counter() - t0
        raise PlanningFailedError(
            f"no collision-free path found from {np.round(qs, 3).tolist()} to {np.round(qg, 3).tolist()} "
            f"with {cfg.planner} after {len(statuses)} attempt(s) in {elapsed:.2f} s "
            f"(limits: {cfg.num_planning_attempts} attempts, {cfg.planning_time_s} s; statuses: "
            f"{', '.join(statuses) or 'none'})")

    @staticmethod
    def _path_array(path) -> np.ndarray:
        return np.array([state_to_array(path.getState(i)) for i in range(path.getStateCount())])
