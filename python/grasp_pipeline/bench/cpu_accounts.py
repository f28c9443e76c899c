"""Where a process's CPU time goes: exclusive per-account CPU seconds of wrapped callables.

:class:`CpuAccounts` replaces chosen functions (an object's method, a module's function) by
timed wrappers for the duration of a ``with`` block and restores them afterwards. Each wrapper
adds the process CPU time (:func:`time.process_time`: every thread, so a renderer's or a
solver's worker threads count where they work) spent inside the call to its account,
*exclusively*: time spent in a nested wrapped call of another account is taken out of the
caller's account, so the accounts never overlap and, with ``other`` (the rest of the block's
CPU time), they add up to the block's total.

Each wrapped call costs two clock reads (about 1 µs together): wrap what is called per
physics step only where the breakdown needs it, and read figures of the same instrumented run
together (their ratios), not against an uninstrumented one.
"""

from __future__ import annotations

import time
from contextlib import ExitStack, contextmanager
from typing import Any, Callable, Iterator

#: The account of the CPU time that no wrapper claimed.
OTHER = "other"


class CpuAccounts:
    """Exclusive CPU seconds per account; see the module doc.

    ``clock``: the time source (default :func:`time.process_time`).

    Usage::

        acc = CpuAccounts()
        with acc.measure():
            acc.wrap(world.camera, "capture", "render")
            ... run ...
        acc.seconds  # {"render": 1.2, ..., "other": 3.4}; acc.total_s the block's CPU time
    """

    def __init__(self, clock: Callable[[], float] = time.process_time) -> None:
        self.clock = clock  # seconds (the process's CPU time; a fake one in tests)
        self.seconds: dict[str, float] = {}
        self.calls: dict[str, int] = {}
        self.total_s = 0.0
        self._stack: list[list] = []  # per open wrapped call: [account, CPU time of nested calls]
        self._restore: ExitStack | None = None

    def _timed(self, account: str, fn: Callable) -> Callable:
        clock = self.clock
        stack = self._stack

        def wrapper(*args: Any, **kwargs: Any) -> Any:
            frame = [account, 0.0]
            stack.append(frame)
            t0 = clock()
            try:
                return fn(*args, **kwargs)
            finally:
                spent = clock() - t0
                stack.pop()
                self.seconds[account] = self.seconds.get(account, 0.0) + spent - frame[1]
                self.calls[account] = self.calls.get(account, 0) + 1
                if stack:
                    stack[-1][1] += spent

        wrapper.__wrapped__ = fn  # type: ignore[attr-defined]
        return wrapper

    def wrap(self, owner: Any, name: str, account: str) -> None:
        """Time ``owner.name`` (a bound method of an instance, a class attribute or a module's
        function) into ``account`` until the :meth:`measure` block ends."""
        if self._restore is None:
            raise RuntimeError("CpuAccounts.wrap is only valid inside 'with accounts.measure()'")
        had_own = name in getattr(owner, "__dict__", {})
        original_own = owner.__dict__[name] if had_own else None
        setattr(owner, name, self._timed(account, getattr(owner, name)))

        def restore() -> None:
            if had_own:
                setattr(owner, name, original_own)
            else:
                delattr(owner, name)

        self._restore.callback(restore)

    @contextmanager
    def measure(self) -> Iterator["CpuAccounts"]:
        """The measured block: wrappers made inside it are removed when it ends; ``total_s``
        is its CPU time and ``seconds["other"]`` what the wrappers did not claim."""
        t0 = self.clock()
        with ExitStack() as restore:
            self._restore = restore
            try:
                yield self
            finally:
                self._restore = None
        self.total_s = self.clock() - t0
        claimed = sum(v for k, v in self.seconds.items() if k != OTHER)
        self.seconds[OTHER] = self.total_s - claimed

    def shares(self) -> dict[str, float]:
        """Each account's share of the block's CPU time (0..1)."""
        total = self.total_s if self.total_s > 0 else 1.0
        return {k: v / total for k, v in self.seconds.items()}
