"""A Rerun recording (``.rrd``) of a run: a subscriber of the event stream.

``attach(events, path, robot)`` subscribes a :class:`RerunRecorder`; ``close()`` finishes
the file. Open it with ``rerun PATH.rrd`` (the viewer ships with ``rerun-sdk``). The Rerun
SDK is an optional extra (``pip install 'grasp-pipeline[rerun]'``): :func:`import_rerun`
raises :class:`RerunUnavailable` saying so, and ``run --rerun`` calls it before the
simulation starts.

The timeline is ``sim_time`` (simulated seconds). What is logged, and when (the entity
paths are listed in :mod:`.rerun_entities`; rates in ``config/rerun.yaml``):

* each perceived frame: the tracks' boxes and the core's time per frame; at most
  ``rerun_frame_rate_hz`` of them also the camera (pose, RGB, depth) and the point cloud —
  and always the latest frame at a key stage (end of the rough view, a scan probe's
  arrival, end of the scan, a new look), so what a stage decided on is in the recording;
* each motion: its planned TCP path (forward kinematics of the trajectory); the executed
  TCP path from the robot's TCP sampled at ``rerun_state_rate_hz`` (with the finger gap);
* each grasp decision: the candidates and the chosen grasp; stages, plans and picks as
  text on the timeline.

``robot`` (the :class:`~grasp_pipeline.robot.protocols.Arm` and ``Gripper`` protocols:
``tcp_pose()``, ``finger_gap_m``) may be None: then the TCP, the executed path and the
finger gap are left out. A failing recorder never stops the robot: it stops recording,
logs a warning and says so in :attr:`problem`; what was written stays a valid recording.
"""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Any, Callable, Optional

import numpy as np

from ..exceptions import GraspPipelineError, InputError
from ..orchestration.events import (EventBus, FrameEvent, GraspEvent, PerceptionEvent, PickEvent,
                                    PlanEvent, StageEvent, Tick)
from . import rerun_entities as ent
from . import rerun_geometry as geo
from .config import RerunConfig
from .serialize import check_writable

log = logging.getLogger("grasp_pipeline.rerun")

INSTALL_HINT = "pip install 'grasp-pipeline[rerun]' (or pip install '.[rerun]' in a checkout)"
#: Oldest SDK with the calls used here (``set_time(duration=)``, ``Scalars``).
MIN_RERUN_VERSION = (0, 23)
TIMELINE = "sim_time"
APPLICATION_ID = "grasp_pipeline"
#: Stages whose latest frame is always recorded (what the stage decided on).
KEY_STAGES = frozenset({"rough_view_done", "probe_arrived", "scan_done", "look_again"})
#: Smallest TCP move that adds a point to the executed path [m] (a still arm adds none).
PATH_STEP_M = 0.001


class RerunUnavailable(GraspPipelineError):
    """The Rerun SDK is not installed (an optional extra) or too old."""


def import_rerun():
    """The ``rerun`` module, or :class:`RerunUnavailable` with the install command."""
    try:
        import rerun
    except ImportError as exc:
        raise RerunUnavailable(f"--rerun needs the Rerun SDK: {INSTALL_HINT}") from exc
    version = tuple(int(x) for x in rerun.__version__.split(".")[:2] if x.isdigit())
    if version < MIN_RERUN_VERSION:
        raise RerunUnavailable(f"--rerun needs rerun-sdk >= {'.'.join(map(str, MIN_RERUN_VERSION))}, "
                               f"found {rerun.__version__}: {INSTALL_HINT}")
    return rerun


def check_recording_path(path) -> Path:
    """A writable ``.rrd`` path (its folder is created), else :class:`InputError`."""
    path = Path(path)
    if path.suffix != ".rrd":
        raise InputError(f"--rerun {path}: a Rerun recording's name ends in .rrd (e.g. out/run.rrd)")
    return check_writable(path, "Rerun recording (--rerun)")


class RerunRecorder:
    """Writes the run's events to ``path`` (see the module doc)."""

    def __init__(self, path, robot=None, config: Optional[RerunConfig] = None) -> None:
        self.rr = import_rerun()
        self.path = Path(path)
        self.robot = robot
        self.config = config or RerunConfig()
        self.problem: Optional[str] = None
        self.logged: dict[str, int] = {}  # what was logged: kind -> count (frames, boxes, ...)
        self._events: Optional[EventBus] = None
        self._frame: Optional[FrameEvent] = None     # the frame perception is processing
        self._pending: Optional[tuple] = None        # (frame, perception) not yet drawn
        self._next_frame_s: Optional[float] = None
        self._next_state_s: Optional[float] = None
        self._pinhole = False
        self._time_s = 0.0                           # the latest event's time
        self._states: list[tuple] = []               # (time, TCP pose, gap mm) not yet sent
        self._perception_ms: list[tuple] = []        # (time, ms) not yet sent
        self._strips: list[list[np.ndarray]] = [[]]  # executed TCP path, one strip a motion
        self._fk: Optional[geo.TcpKinematics] = None
        self.rec = self.rr.RecordingStream(APPLICATION_ID)
        import rerun.blueprint as rrb

        self.rec.save(str(self.path), default_blueprint=ent.default_blueprint(rrb))
        ent.log_static(self.rr, self.rec)

    def _handlers(self) -> dict[type, Callable[[Any], None]]:
        return {Tick: self.on_tick, FrameEvent: self.on_frame, PerceptionEvent: self.on_perception,
                PlanEvent: self.on_plan, GraspEvent: self.on_grasp, StageEvent: self.on_stage,
                PickEvent: self.on_pick}

    def attach(self, events: EventBus) -> "RerunRecorder":
        self._events = events
        for event_type, fn in self._handlers().items():
            if event_type is Tick and self.robot is None:
                continue
            events.subscribe(event_type, fn)
        return self

    def _detach(self) -> None:
        if self._events is not None:
            for event_type, fn in self._handlers().items():
                self._events.unsubscribe(event_type, fn)

    # ---- the guard: a recorder never stops the robot ---------------------------------
    def _safely(self, fn: Callable[[Any], None], ev) -> None:
        try:
            self._time_s = max(self._time_s, float(ev.time_s))
            self.rec.set_time(TIMELINE, duration=float(ev.time_s))
            fn(ev)
        except Exception as exc:  # disk full, a bad array: the robot carries on
            self.problem = (f"Rerun recording stopped at t={float(ev.time_s):.2f} s: "
                            f"{type(exc).__name__}: {exc}")
            log.warning("%s", self.problem)
            self._detach()

    def _count(self, kind: str) -> None:
        self.logged[kind] = self.logged.get(kind, 0) + 1

    # ---- subscribers -------------------------------------------------------------------
    def on_tick(self, ev: Tick) -> None:
        if self._next_state_s is not None and ev.time_s + 1e-9 < self._next_state_s:
            return
        self._next_state_s = (ev.time_s if self._next_state_s is None else self._next_state_s) \
            + 1.0 / self.config.rerun_state_rate_hz
        self._safely(self._state, ev)

    def on_frame(self, ev: FrameEvent) -> None:
        self._frame = ev

    def on_perception(self, ev: PerceptionEvent) -> None:
        self._safely(self._perception, ev)

    def on_plan(self, ev: PlanEvent) -> None:
        self._safely(self._plan, ev)

    def on_grasp(self, ev: GraspEvent) -> None:
        self._safely(self._grasp, ev)

    def on_stage(self, ev: StageEvent) -> None:
        self._safely(self._stage, ev)

    def on_pick(self, ev: PickEvent) -> None:
        self._safely(self._pick, ev)

    # ---- what each event logs ----------------------------------------------------------
    def _state(self, ev: Tick) -> None:
        T = np.asarray(self.robot.tcp_pose(), dtype=float)
        self._states.append((float(ev.time_s), T.copy(), 1e3 * float(self.robot.finger_gap_m)))
        self._count("states")
        strip = self._strips[-1]
        if not strip or np.linalg.norm(T[:3, 3] - strip[-1]) >= PATH_STEP_M:
            strip.append(T[:3, 3].copy())

    def _send_series(self) -> None:
        """The buffered samples (TCP, finger gap, perception time) as columns: one call each
        instead of one per sample (sent at every stage, pick and the end)."""
        if self._states:
            t = np.array([s[0] for s in self._states])
            ent.send_tcp(self.rr, TIMELINE, self.rec, t, np.stack([s[1] for s in self._states]))
            ent.send_scalars(self.rr, TIMELINE, self.rec, ent.FINGER_GAP, t, [s[2] for s in self._states])
            self._states = []
        if self._perception_ms:
            t, ms = zip(*self._perception_ms)
            ent.send_scalars(self.rr, TIMELINE, self.rec, ent.PERCEPTION_MS, t, ms)
            self._perception_ms = []

    def _perception(self, ev: PerceptionEvent) -> None:
        ent.log_boxes(self.rr, self.rec, geo.track_boxes(ev.tracks))
        self._perception_ms.append((float(ev.time_s), float(ev.result.raw.ms_total)))
        self._count("perceived_frames")
        frame = self._frame if self._frame is not None and self._frame.time_s == ev.time_s else None
        if frame is None:
            return
        if self._next_frame_s is None or ev.time_s + 1e-9 >= self._next_frame_s:
            self._next_frame_s = float(ev.time_s) + 1.0 / self.config.rerun_frame_rate_hz
            self._draw_frame(frame, ev)
        else:
            self._pending = (frame, ev)

    def _draw_frame(self, frame: FrameEvent, perceived: PerceptionEvent) -> None:
        cfg = self.config
        ent.log_camera(self.rr, self.rec, frame.frame, cfg.rerun_jpeg_quality, self._pinhole)
        self._pinhole = True
        obj, env = geo.split_cloud(perceived.result, cfg.rerun_max_object_points,
                                   cfg.rerun_max_environment_points)
        ent.log_cloud(self.rr, self.rec, obj, env)
        self._pending = None
        self._count("camera_frames")

    def _plan(self, ev: PlanEvent) -> None:
        text = (f"{ev.kind}: {ev.method}, planned in {ev.planning_ms:.0f} ms, timed in "
                f"{ev.timing_ms:.0f} ms, {ev.duration_s:.2f} s")
        ent.log_text(self.rr, self.rec, ent.PLANS, text)
        self._count("plans")
        self._log_executed()
        if self._strips[-1]:  # a new motion: a new strip, continuing from where the arm is
            self._strips.append([self._strips[-1][-1]])
        traj = ev.trajectory
        if traj is None or len(traj.q) == 0:
            return
        if self._fk is None:
            self._fk = geo.TcpKinematics()
        rows = geo.sample_rows(len(traj.q), self.config.rerun_plan_samples)
        ent.log_path(self.rr, self.rec, ent.PATH_PLANNED, [self._fk.positions(np.asarray(traj.q)[rows])],
                     geo.PLANNED_RGB, f"planned {ev.kind}")

    def _grasp(self, ev: GraspEvent) -> None:
        ent.log_grasps(self.rr, self.rec, list(ev.candidates), ev.chosen)
        self._count("grasp_decisions")

    def _stage(self, ev: StageEvent) -> None:
        ent.log_text(self.rr, self.rec, ent.STAGES, f"{ev.name} {ev.detail}".strip())
        self._count("stages")
        self._log_executed()
        self._send_series()
        if ev.name in KEY_STAGES and self._pending is not None:
            frame, perceived = self._pending
            self.rec.set_time(TIMELINE, duration=float(perceived.time_s))
            self._draw_frame(frame, perceived)

    def _pick(self, ev: PickEvent) -> None:
        r = ev.result
        ok = bool(getattr(r, "success", False))
        text = "picked" if ok else f"failed at {getattr(r, 'failed_stage', None)}: {getattr(r, 'message', '')}"
        ent.log_text(self.rr, self.rec, ent.PICKS, text, "INFO" if ok else "WARN")
        ent.clear_grasps(self.rr, self.rec)
        self._count("picks")
        self._send_series()

    def _log_executed(self) -> None:
        if self.robot is not None:
            ent.log_path(self.rr, self.rec, ent.PATH_EXECUTED, self._strips, geo.EXECUTED_RGB)

    # ---- the end -----------------------------------------------------------------------
    def close(self) -> Optional[str]:
        """Finish the file; returns its path (None when recording failed before anything)."""
        self._detach()
        try:
            if self.problem is None:
                self.rec.set_time(TIMELINE, duration=self._time_s)
                self._log_executed()
                self._send_series()
            self.rec.flush()
            self.rec.disconnect()
        except Exception as exc:
            self.problem = self.problem or f"Rerun recording not finished: {type(exc).__name__}: {exc}"
            log.warning("%s", self.problem)
        return str(self.path) if self.path.exists() else None


def attach(events: EventBus, path, robot=None, config: Optional[RerunConfig] = None) -> RerunRecorder:
    """Record ``events`` into the ``.rrd`` file ``path`` (``robot``: for the TCP, the executed
    path and the finger gap). Raises :class:`RerunUnavailable` without the SDK; call
    :meth:`RerunRecorder.close` when the run ends."""
    return RerunRecorder(check_recording_path(path), robot, config).attach(events)
