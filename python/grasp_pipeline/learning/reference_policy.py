"""The reference policy: the pipeline itself, acting through the environment's actions.

The pipeline's parts (perception loop, active scan, planner, grasp action) are built by the
composition root (:func:`grasp_pipeline.app.sim_system.build_system`) on an
:class:`~.robot_adapter.EnvRobot`, so every command to the robot is an ``env.step(action)``;
it perceives through the simulator's eye-in-hand camera and contact monitor as ``run`` does,
and reads the task sentence — never the target's name or pose. One episode: a rough view from
the start pose, the active scan (``env.yaml`` ``reference_scan``), the task's object resolved
among the perceived objects by its description (:mod:`grasp_pipeline.language`: the words of
the task the resolver knows, relaxed step by step when they name no single object:
:mod:`.task_resolution`), then up to
``reference_attempts`` picks of it into the tray;
after its last attempt it holds still for ``reference_wait_s``. The environment ends the
episode when the target rests in the tray (or at its time limit).
"""

from __future__ import annotations

import logging
import re
from dataclasses import dataclass, field
from typing import Callable, Optional

from ..orchestration import PickContext, pick_object
from .robot_adapter import EnvRobot, EpisodeEnded

log = logging.getLogger(__name__)


@dataclass
class ReferenceOutcome:
    """How an episode of the reference policy went: ``failed_stage`` and ``message`` are its
    own account of why it stopped (a stage of the pick — ``LOOK``, ``RESOLVE``, ``SELECT``,
    ``GRASP``, ..., ``PLACE`` — or ``TIME_LIMIT``; empty after a success);
    ``terminated``/``truncated`` as the environment ended the episode (both False when the
    policy stopped first); ``picks``: its finished pick results."""

    failed_stage: str = ""
    message: str = ""
    terminated: bool = False
    truncated: bool = False
    description: str = ""
    picks: list = field(default_factory=list)
    steps: int = 0


def task_description(task: str, template: str, language_config) -> str:
    """The words of ``task``'s object phrase that the language resolver knows, as a
    description ("pick up the red triangular prism and put it in the tray" -> "the red
    object"); ``template``: the task template with ``{object}``."""
    from ..language.parse import vocabulary
    from .targets import task_phrase

    phrase = task_phrase(task, template)
    known = set().union(*vocabulary(language_config).values())
    words = [w for w in re.split(r"[\s_]+", phrase.lower()) if w in known]
    if not any(w in vocabulary(language_config)["shape"] for w in words):
        words.append("object")
    return "the " + " ".join(words)


class ReferencePolicy:
    """``run_episode(env, obs, info)`` plays one episode (see the module doc). ``prepare``:
    called with the built system before it acts (e.g. to attach a recorder to its events)."""

    name = "reference"

    def __init__(self, settings, prepare: Optional[Callable] = None) -> None:
        self.settings, self.prepare = settings, prepare

    def run_episode(self, env, obs: dict, info: dict) -> ReferenceOutcome:
        from ..app.sim_system import build_system

        robot = EnvRobot(env, obs, info)
        system = build_system(None, self.settings, robot=robot)
        out = ReferenceOutcome(description=task_description(
            info["task"], self.settings.record.task_template, self.settings.language))
        try:
            if self.prepare is not None:
                self.prepare(system)
            out.failed_stage, out.message = self._act(system, out)
            system.rt.spin(self.settings.env.reference_wait_s, look=False)
            if not out.failed_stage:
                out.failed_stage, out.message = "PLACE", "placed, but the target does not rest in the tray"
        except EpisodeEnded as end:
            out.terminated, out.truncated = end.terminated, not end.terminated
            if end.terminated:
                out.failed_stage = out.message = ""
            else:
                out.failed_stage, out.message = "TIME_LIMIT", str(end)
        finally:
            out.steps = robot.steps
            system.close()
        return out

    def _act(self, system, out: ReferenceOutcome) -> tuple[str, str]:
        """Look, scan, resolve, pick; (stage, why) it stopped (empty when a pick succeeded)."""
        from ..app.run import default_grasp_source
        from ..language import ObservationRecorder

        s = self.settings
        observations = ObservationRecorder(s.language).attach(system.events)
        system.rt.spin(s.scan.rough_view_s)
        if system.loop.plane is None:
            return "LOOK", "no table plane found from the start pose"
        if s.env.reference_scan:
            _scan(system, s)
        ctx = PickContext(system.rt, system.loop, system.action,
                          system.scanner if s.env.reference_scan else None, s,
                          default_grasp_source(s), place=True)
        stage = message = ""
        for _attempt in range(s.env.reference_attempts):
            xy, message = _resolve(system, s, out.description, observations)
            if xy is None:
                return "RESOLVE", message
            row = pick_object(ctx, xy)
            out.picks.append(row)
            if row.success and row.placed:
                return "", ""
            stage, message = row.failed_stage or "PLACE", row.message
        return stage, message


def _scan(system, settings) -> None:
    """The active scan from the start pose, then the settle view (as ``run``)."""
    trig = system.scanner.trigger()
    if trig.accepted:
        try:
            system.rt.run(system.scanner.task, settings.scan.scan_timeout_s)
        except TimeoutError as exc:
            system.world.hold()
            log.warning("scan: %s", exc)
    system.rt.spin(settings.scan.settle_view_s)


def _resolve(system, settings, description: str, observations):
    """((x, y) of the perceived object the description names, "") or (None, why not)."""
    from ..language import LanguageError, NoMatchError, perceive_objects, resolve_picks
    from ..language.exceptions import AmbiguousDescriptionError
    from .task_resolution import resolution_ladder

    margin = settings.grasp.target_fixture_margin_m
    tracks = [t for t in system.loop.tracks()
              if system.cell.pick_target_note(t.smoothed.center[:2], margin) is None]
    objects = perceive_objects(tracks, observations, settings.language)
    refusals: list[str] = []
    for d, among in resolution_ladder(description, objects, settings.language):
        if not among:
            continue
        try:
            (xy,) = resolve_picks([d], among, [], settings.language)
            return xy, ""
        except (NoMatchError, AmbiguousDescriptionError) as exc:
            if str(exc) not in refusals:
                refusals.append(str(exc))
        except LanguageError as exc:
            return None, "; then ".join(refusals + [str(exc)])
    return None, "; then ".join(refusals)
