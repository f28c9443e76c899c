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
