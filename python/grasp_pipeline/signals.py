"""Ctrl-C and SIGTERM as ``KeyboardInterrupt``, counted, so that a signal is never lost.

Within :func:`interrupts_raise` both signals raise ``KeyboardInterrupt`` in the main thread (the
command then stops cleanly: the arm holds, the report says interrupted) and are counted. Some
libraries catch ``BaseException`` around their own steps (trimesh does while it reads a textured
OBJ), which swallows the interrupt; a loop over such calls takes :func:`received` before and
calls :func:`raise_if_received_since` after each step, which raises it again.

:func:`held` keeps both signals back for a short block that must not be cut in half (starting a
worker process: an interrupt between its creation and the hand-over of its instructions would
leave it reading nothing) and delivers them after it.
"""

from __future__ import annotations

import signal
import threading
from contextlib import contextmanager
from typing import Iterator

_received = 0

#: The signals that stop a command (Ctrl-C and ``kill``).
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)


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


@contextmanager
def held() -> Iterator[None]:
    """Keep Ctrl-C / SIGTERM back during the block and deliver them after it, each once, to
    whatever handles them then (main thread; elsewhere the block runs unchanged).

    They are blocked in this thread's signal mask, which a process started inside the block
    inherits (a worker unblocks them itself once it is ready to stop cleanly: see
    :func:`release_held`), and caught meanwhile by a handler that only notes them (a signal the
    kernel hands to another thread of this process is noted too)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    noted: list[int] = []
    previous = {sig: signal.signal(sig, lambda signum, frame: noted.append(signum))
                for sig in STOP_SIGNALS if signal.getsignal(sig) not in (signal.SIG_IGN, None)}
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, STOP_SIGNALS)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, mask)  # those kept back reach the note now
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        for sig in dict.fromkeys(noted):
            signal.raise_signal(sig)


def release_held() -> None:
    """Unblock the signals a process inherited from :func:`held`: one that arrived meanwhile is
    delivered now (Ctrl-C raises ``KeyboardInterrupt`` here, SIGTERM ends the process)."""
    signal.pthread_sigmask(signal.SIG_UNBLOCK, STOP_SIGNALS)
