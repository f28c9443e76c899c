"""A cooperative runtime: one simulated world, camera frames to perception, background tasks.

The simulator is stepped in one thread. Long-running behaviours (the active scan, the
grasp action) are *tasks*: Python generators that yield whenever they wait for simulated
time to pass. :meth:`Runtime.step` advances every running task once and, if none of them
stepped the world itself (an executor stepping a trajectory does), steps the world by one
physics step. Camera frames reach perception through the world's frame listeners, so
perception runs at the camera rate whoever steps. A trigger such as ``scan.trigger()``
therefore returns at once and the work happens while the caller spins the runtime —
the non-blocking service semantics of method.md §6, without threads.

Frames on demand: the camera renders only while someone looks
(:meth:`Runtime.looking`, the robot's ``request_frames``). :meth:`Runtime.spin` looks by
default (it is the "wait here and watch" of the rough view and the settle views);
:meth:`Runtime.spin_until` looks only when asked; tasks open their own looks (the scan's
dwell). Motions look at nothing, so they run without rendering.
"""

from __future__ import annotations

import logging
from contextlib import contextmanager, nullcontext
from dataclasses import dataclass, field
from typing import Any, Callable, ContextManager, Generator, Iterator, Optional

from .. import signals
from .events import EventBus, Tick

log = logging.getLogger("grasp_pipeline.runtime")

TaskGen = Generator[None, None, Any]


@dataclass
class Task:
    """A running behaviour; ``result`` / ``error`` are set when it ends."""

    name: str
    gen: TaskGen
    done: bool = False
    result: Any = None
    error: Optional[BaseException] = None
    activity: str = field(init=False, repr=False)  # what an interrupt's message says it cut

    def __post_init__(self) -> None:
        self.activity = f"task {self.name} ran"


@dataclass
class Runtime:
    """Steps ``world`` (the robot's clock) and the tasks; publishes a
    :class:`~.events.Tick` after every step when anyone listens."""

    world: Any
    events: EventBus = field(default_factory=EventBus)
    tasks: list = field(default_factory=list)

    def start(self, name: str, gen: TaskGen) -> Task:
        task = Task(name, gen)
        self.tasks.append(task)
        return task

    def step(self) -> None:
        world = self.world
        t_before = world.time_s
        for task in tuple(self.tasks):
            mark = signals.received()
            try:
                next(task.gen)
                # an interrupt the task swallowed (a library's ``except BaseException``) is raised
                signals.raise_if_received_since(mark, task.activity)
            except StopIteration as stop:
                task.done, task.result = True, stop.value
            except Exception as exc:  # a task failure must not kill the runtime
                # Ctrl-C inside a C extension's import can come out as ImportError: still Ctrl-C
                signals.raise_if_received_since(mark, task.activity)
                log.exception("task %s failed", task.name)
                task.done, task.error = True, exc
            if task.done:
                self.tasks.remove(task)
        t_now = world.time_s
        if t_now == t_before:
            world.step(1)
            t_now = world.time_s
        if self.events.wants(Tick):
            self.events.publish(Tick(float(t_now)))

    @contextmanager
    def looking(self) -> Iterator[None]:
        """Camera frames are wanted while this context is open (the robot's
        ``request_frames``; a robot without a camera makes it a no-op)."""
        with _frame_request(self.world):
            yield

    def spin_until(self, done: Callable[[], bool], timeout_s: float, look: bool = False) -> bool:
        """Step until ``done()`` (True) or ``timeout_s`` of simulated time passed (False);
        ``look``: request camera frames meanwhile."""
        t_end = self.world.time_s + timeout_s
        with self.looking() if look else nullcontext():
            while not done():
                if self.world.time_s >= t_end:
                    return False
                self.step()
        return True

    def spin(self, duration_s: float, look: bool = True) -> None:
        """Let ``duration_s`` of simulated time pass; ``look`` (default): watching, i.e.
        with camera frames requested (rough view, settle views)."""
        t_end = self.world.time_s + duration_s
        with self.looking() if look else nullcontext():
            while self.world.time_s < t_end - 0.5 * self.world.timestep_s:
                self.step()

    def run(self, task: Task, timeout_s: float) -> Any:
        """Spin until ``task`` ends; re-raise its error; TimeoutError after ``timeout_s``."""
        if not self.spin_until(lambda: task.done, timeout_s):
            task.gen.close()  # runs the task's cleanup (an executor holds the arm)
            if task in self.tasks:
                self.tasks.remove(task)
            raise TimeoutError(f"task {task.name} did not finish within {timeout_s} s (simulated)")
        if task.error is not None:
            raise task.error
        return task.result


def wait_s(world, duration_s: float) -> TaskGen:
    """Task helper: let ``duration_s`` of simulated time pass."""
    t_end = world.time_s + duration_s
    while world.time_s < t_end - 0.5 * world.timestep_s:
        yield


def then_cleanup(body: TaskGen, cleanup: Callable[[], Optional[TaskGen]]) -> TaskGen:
    """Task helper: run ``body``, then the task ``cleanup()`` returns (None: nothing), also when
    ``body`` failed with an error (which is raised again after the cleanup). Not when the task
    is closed or interrupted (``GeneratorExit``, ``KeyboardInterrupt``): a task that is ending
    must not wait for simulated time any more, and the arm holds where it is."""
    try:
        result = yield from body
    except Exception:
        yield from cleanup() or ()
        raise
    yield from cleanup() or ()
    return result


def _frame_request(world) -> ContextManager[None]:
    request = getattr(world, "request_frames", None)
    return nullcontext() if request is None else request()
