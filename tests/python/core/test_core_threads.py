"""Stateful core objects shared by several Python threads: calls are serialised by a mutex
in the bindings (GIL released while waiting), so nothing crashes, deadlocks or corrupts.

Regression: one PerceptionSession used from two threads at once crashed the interpreter
(``double free or corruption``): both threads ran Perception::process on the same tracker
with the GIL released. Each hammer runs in a child interpreter so that a crash fails the
test instead of the whole run.
"""

import threading

import numpy as np
import pytest

from grasp_pipeline import _core
from isolated import describe, run_isolated

# A table with 30 small boxes: ~3 ms per frame and 30 tracks, so a race in the tracker
# shows within a few hundred frames.
CLOUD = """
import numpy as np, threading
from test_core_bindings import table_cloud, cube_cloud
cloud = np.vstack([table_cloud(20000)] + [cube_cloud((0.35 + 0.07 * i, -0.2 + 0.1 * j), n=150,
                  seed=i * 7 + j) for i in range(6) for j in range(5)]).astype(np.float32)
errors = []
def run_threads(target, n=4):
    th = [threading.Thread(target=target, args=(k,)) for k in range(n)]
    [t.start() for t in th]
    [t.join(120) for t in th]
    assert not any(t.is_alive() for t in th), "a thread hangs (deadlock?)"
    assert errors == [], errors[:3]
"""


def test_one_session_hammered_by_four_threads_neither_crashes_nor_deadlocks():
    code = CLOUD + """
from grasp_pipeline.perception import PerceptionSession
s = PerceptionSession()
def work(k):
    try:
        for i in range(300):
            s.process(cloud + np.float32([0.002 * ((i + k) % 5), 0, 0]), [0.5, 0, 0.6], 0.0)
            s.tracks(); s.plane; s.plane_locked; s.tracker.last_gate
            if i % 97 == k:
                s.reset()
    except Exception as exc:
        errors.append(repr(exc))
run_threads(work)
print("frames", s.frames)
"""
    res = run_isolated(code, timeout_s=300)
    assert res.returncode == 0, describe(res)
    assert "frames" in res.stdout


def test_views_and_standalone_objects_are_serialised_too():
    """Readers of Perception.tracker / .scene_filter.persistence while other threads process;
    a standalone Tracker / PlanePersistence / SceneFilter shared by threads."""
    code = CLOUD + """
from grasp_pipeline import _core
per = _core.Perception(_core.SceneFilterParams(), _core.ObbParams())
fr = per.process(cloud, [0.5, 0, 0.6], 0.0)
ests, qs = list(fr.estimates), [v.quality for v in fr.views]
tracker, sf = per.tracker, per.scene_filter
alone = _core.Tracker(_core.ObbParams())
pers = _core.PlanePersistence(_core.SceneFilterParams())
filt = _core.SceneFilter(_core.SceneFilterParams())
plane = _core.Plane([0, 0, 1], -0.2)
def work(k):
    try:
        for i in range(300):
            if k in (0, 1):  # two writers on the Perception, readers through its views
                per.process(cloud + np.float32([0.002 * ((i + k) % 5), 0, 0]), [0.5, 0, 0.6], 0.0)
                [t.smoothed.center for t in tracker.tracks]; sf.persistence.state; sf.frame_index
                tracker.prior_theta([0.4, 0.0, 0.25])
                _core.estimate_with_priors([cloud[-150:]], plane, _core.ObbParams(), tracker)
            elif k in (2, 3):  # two writers on a standalone tracker and plane persistence
                alone.update(ests, qs, float(i)); alone.tracks; alone.retire(float(i) - 5.0)
                pers.update(plane if i % 3 else None); pers.state
                if i % 50 == 0: alone.reset(); pers.reset()
            else:
                filt.process(cloud[::2]); filt.persistence.locked
                if i % 50 == 0: filt.reset()
    except Exception as exc:
        errors.append(repr(exc))
run_threads(work, n=6)
print("ok")
"""
    res = run_isolated(code, timeout_s=300)
    assert res.returncode == 0, describe(res)


def test_the_gil_is_released_while_a_thread_waits_or_works():
    """While one thread processes big frames, another Python thread keeps running."""
    per = _core.Perception(_core.SceneFilterParams(), _core.ObbParams())
    rng = np.random.default_rng(0)
    big = np.column_stack([rng.uniform(0, 1, 400_000), rng.uniform(0, 1, 400_000),
                           0.2 + rng.normal(0, 0.002, 400_000)]).astype(np.float32)
    done = threading.Event()
    ticks = []

    frames = 60  # per worker: long enough (~0.15 s on a fast machine) for many ticks

    def process():
        for _ in range(frames):
            per.process(big, [0.5, 0.5, 0.6], 0.0)
        done.set()

    workers = [threading.Thread(target=process) for _ in range(2)]
    for w in workers:
        w.start()
    while not done.is_set():
        ticks.append(1)  # pure Python work: only runs if the workers released the GIL
        done.wait(0.001)
    for w in workers:
        w.join(60)
    assert len(ticks) > 10, len(ticks)
    assert per.scene_filter.frame_index == 2 * frames  # every frame counted exactly once


def test_views_keep_their_owner_alive_and_see_its_state():
    per = _core.Perception(_core.SceneFilterParams(), _core.ObbParams())
    view = per.scene_filter.persistence
    tracker = per.tracker
    pts = np.column_stack([np.random.default_rng(1).uniform(0, 1, (3000, 2)),
                           np.full(3000, 0.2)]).astype(np.float32)
    per.process(pts, [0.5, 0.5, 0.6], 0.0)
    del per  # the views own a share of the Perception
    assert view.locked and view.state.lock.height_m == pytest.approx(0.2)
    assert tracker.tracks == []


def test_session_frame_count_is_exact_under_threads():
    from grasp_pipeline.perception import PerceptionSession

    s = PerceptionSession()
    pts = np.column_stack([np.random.default_rng(2).uniform(0, 1, (2000, 2)),
                           np.full(2000, 0.2)]).astype(np.float32)
    th = [threading.Thread(target=lambda: [s.process(pts, [0.5, 0.5, 0.6], 0.0) for _ in range(25)])
          for _ in range(4)]
    for t in th:
        t.start()
    for t in th:
        t.join(60)
    assert s.frames == 100
    s.reset()
    assert s.frames == 0
