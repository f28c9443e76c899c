"""A job module whose import in a worker process is interrupted as Ctrl-C in a terminal would
interrupt it while the worker starts: SIGINT to the worker and to the process that started it
when ``INTERRUPT_START_FROM`` names the process that started it (the test's own process imports it
without effect)."""

import os
import signal

if os.environ.get("INTERRUPT_START_FROM") == str(os.getppid()):  # a worker, unpickling its job
    os.kill(os.getppid(), signal.SIGINT)
    os.kill(os.getpid(), signal.SIGINT)


def echo(task: tuple) -> dict:
    return {"index": task[0]}
