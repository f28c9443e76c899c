"""Ctrl-C and SIGTERM as ``KeyboardInterrupt``, counted, so that a signal is never lost.

Within :func:`interrupts_raise` both signals raise ``KeyboardInterrupt`` in the main thread (the
command then stops cleanly: the arm holds, the report says interrupted) and are counted. Some
libraries catch ``BaseException`` around their own steps (trimesh does while it reads a textured
OBJ), which swallows the interrupt; a loop over such calls takes :func:`received` before and
calls :func:`raise_if_received_since` after each step, which raises it again.
"""

from __future__ import annotations

import signal
from contextlib import contextmanager
from typing import Iterator

_received = 0


def received() -> int:
    """How many Ctrl-C / SIGTERM this process has received inside :func:`interrupts_raise`."""
    return _received


def raise_if_received_since(mark: int, what: str) -> None:
    """``KeyboardInterrupt`` when a signal came after :func:`received` returned ``mark`` (one a
    library may have swallowed)."""
    if _received != mark:
        raise KeyboardInterrupt(f"signal received while {what}")


def _handler(signum, frame):
    global _received
    _received += 1
    raise KeyboardInterrupt(f"signal {signum}")


@contextmanager
def interrupts_raise() -> Iterator[None]:
    """Within the block SIGTERM, and SIGINT unless it is ignored (``nohup``), raise a counted
    KeyboardInterrupt (main thread only; elsewhere the block runs unchanged)."""
    previous = {}
    try:
        for sig in (signal.SIGINT, signal.SIGTERM):
            if sig == signal.SIGINT and signal.getsignal(sig) is signal.SIG_IGN:
                continue
            previous[sig] = signal.signal(sig, _handler)
    except ValueError:  # not the main thread
        pass
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
