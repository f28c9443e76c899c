"""Job functions for the scheduler tests (imported by the worker processes: module level)."""

import os


def echo_or_die(task: tuple) -> dict:
    """``(index, "die")`` kills its own process (as a segfault would); else echoes."""
    index, what = task
    if what == "die":
        os.abort()
    return {"index": index, "value": what, "pid": os.getpid()}


def failed(task: tuple, error: str, wall_s: float) -> dict:
    return {"index": task[0], "error": error}


def echo_pid(task: tuple) -> dict:
    """``(index, what)``: echoes with the process id; ``what == "fail"`` returns a failed record."""
    index, what = task
    return {"index": index, "value": what, "pid": os.getpid(), "error": "failed" if what == "fail" else None}


def ompl_draws(task: tuple) -> dict:
    """Three draws of a fresh OMPL generator after a planner was made, as a job's planning sees them."""
    import ompl.util as ou

    from grasp_pipeline.motion.config import MotionConfig
    from grasp_pipeline.motion.planner import JointPlanner

    JointPlanner(validator=None, config=MotionConfig())
    rng = ou.RNG()
    return {"index": task[0], "draws": [rng.uniform01() for _ in range(3)], "pid": os.getpid()}


def slow_exit(task: tuple) -> dict:
    """``(index, seconds)``: sleeps, after registering an exit handler that takes a while (as
    closing MuJoCo's EGL display can) and says when it is done."""
    import atexit
    import sys
    import time

    def close_display() -> None:
        time.sleep(2.0)
        print("exit handlers done", file=sys.stderr, flush=True)

    atexit.register(close_display)
    time.sleep(task[1])
    return {"index": task[0]}
