"""Records the pipeline's picks as episodes: a subscriber of the run's event stream.

:class:`EpisodeRecorder` samples the robot at ``fps_hz`` of simulated time on the event
stream's :class:`~grasp_pipeline.orchestration.events.Tick` (published after every physics
step, so a sample lies at most one step — 2 ms — after its nominal time) and, at each
sample, renders its own camera views (``render``, e.g. :class:`.camera_views.RecordingViews`;
never the eye-in-hand camera's frames, which render only when perception looks). It reads
the robot and never commands it, so the pipeline's decisions are those of an unrecorded run.

Episode boundaries: recording starts at the stage ``start_stage`` (``scan_done``: the arm is
back at its start pose after the scan); each :class:`~grasp_pipeline.orchestration.events.PickEvent`
closes the running episode (the pick, its place and the return home) and opens the next one
at once, so an episode also holds the fresh look before its pick. Frames after the last pick
belong to no episode. ``describe(pick_result) -> (task, object_name)`` labels an episode.
"""

from __future__ import annotations

from typing import Callable, Optional

import numpy as np
from scipy.spatial.transform import Rotation

from ..orchestration.events import EventBus, PickEvent, StageEvent, Tick
from .episode import Episode

#: Stage at which the first episode starts.
START_STAGE = "scan_done"
#: A sample is due when the clock is within this of its nominal time [s].
_DUE_SLACK_S = 1e-9


def pick_outcome(row) -> tuple[bool, str]:
    """(success, failed stage) of a :class:`~grasp_pipeline.results.PickResult` after the
    ground-truth evaluation: success = the robot reported success and the object lies in the
    tray; a reported success whose object is not in the tray fails at ``VERIFY``."""
    ok = bool(row.success and row.placed and not row.failed_stage)
    if ok:
        return True, ""
    return False, row.failed_stage or ("VERIFY" if row.success else "UNKNOWN")


class _Buffer:
    """The samples of the running episode."""

    def __init__(self) -> None:
        self.t: list = []
        self.state: list = []
        self.pose: list = []
        self.command: list = []
        self.images: dict = {}
        self.depths: dict = {}


class EpisodeRecorder:
    """Subscribe with :meth:`attach`; finished episodes go to ``on_episode(episode)``.

    ``robot``: the arm, gripper and clock (``q``, ``finger_gap_m``, ``tcp_pose()``,
    ``reference()``, ``gripper_target_m``, ``time_s``); ``render() -> (images, depths)``:
    dicts camera name -> image, or None for no images."""

    def __init__(self, robot, fps_hz: float, on_episode: Callable[[Episode], None],
                 describe: Callable[[object], tuple[str, Optional[str]]],
                 render: Optional[Callable[[], tuple[dict, dict]]] = None,
                 start_stage: str = START_STAGE) -> None:
        self.robot, self.period_s = robot, 1.0 / float(fps_hz)
        self.on_episode, self.describe, self.render = on_episode, describe, render
        self.start_stage = start_stage
        self.buffer: Optional[_Buffer] = None
        self.next_t = 0.0
        self.episodes = 0

    def attach(self, events: EventBus) -> "EpisodeRecorder":
        events.subscribe(StageEvent, self.on_stage)
        events.subscribe(Tick, self.on_tick)
        events.subscribe(PickEvent, self.on_pick)
        return self

    def _open(self, t: float) -> None:
        self.buffer = _Buffer()
        self.next_t = t
        self._sample(t)

    def on_stage(self, ev: StageEvent) -> None:
        if ev.name == self.start_stage and self.buffer is None and self.episodes == 0:
            self._open(float(ev.time_s))

    def on_tick(self, ev: Tick) -> None:
        if self.buffer is not None and ev.time_s >= self.next_t - _DUE_SLACK_S:
            self._sample(float(ev.time_s))

    def _sample(self, t: float) -> None:
        r, b = self.robot, self.buffer
        T = np.asarray(r.tcp_pose(), dtype=float)
        q_ref, _qd_ref = r.reference()
        b.t.append(t)
        b.state.append(np.append(np.asarray(r.q, dtype=float), float(r.finger_gap_m)))
        b.pose.append(np.concatenate([T[:3, 3], Rotation.from_matrix(T[:3, :3]).as_quat()]))
        b.command.append(np.append(np.asarray(q_ref, dtype=float), float(r.gripper_target_m)))
        if self.render is not None:
            images, depths = self.render()
            for name, img in images.items():
                b.images.setdefault(name, []).append(np.asarray(img, dtype=np.uint8))
            for name, d in depths.items():
                b.depths.setdefault(name, []).append(np.asarray(d, dtype=np.float32))
        # the next sample is due one period after this one's nominal time (no drift)
        self.next_t += self.period_s
        if self.next_t <= t:
            self.next_t = t + self.period_s

    def on_pick(self, ev: PickEvent) -> None:
        if self.buffer is None:
            return
        b = self.buffer
        task, obj = self.describe(ev.result)
        success, stage = pick_outcome(ev.result)
        episode = build_episode(b, task, success, stage, str(ev.result.message or ""), obj)
        self.episodes += 1
        self.on_episode(episode)
        self._open(float(ev.time_s))


def build_episode(b: _Buffer, task: str, success: bool, stage: str, message: str,
                  obj: Optional[str]) -> Episode:
    """The episode of buffer ``b`` (actions and end-effector deltas from its samples)."""
    state, pose = np.asarray(b.state), np.asarray(b.pose)
    command = np.asarray(b.command)
    action = np.vstack([command[1:], command[-1:]])   # the targets in force at the next frame
    rot = Rotation.from_quat(pose[:, 3:])
    delta = np.zeros((len(pose), 7))
    delta[:-1, :3] = pose[1:, :3] - pose[:-1, :3]
    delta[:-1, 3:6] = (rot[1:] * rot[:-1].inv()).as_rotvec()
    delta[:, 6] = action[:, 7]
    f32 = np.float32
    return Episode(task=task, success=success, failed_stage=stage, message=message, object=obj,
                   time_s=np.asarray(b.t, dtype=np.float64), state=state.astype(f32),
                   ee_pose=pose.astype(f32), action=action.astype(f32),
                   action_ee_delta=delta.astype(f32),
                   images={k: np.stack(v) for k, v in b.images.items()},
                   depths={k: np.stack(v) for k, v in b.depths.items()})
