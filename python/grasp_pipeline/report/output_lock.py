"""A marker in an output folder while a command writes there: two commands writing the same
folder warn instead of mixing their files silently (the last report written would win).

:func:`claim_output` writes ``<folder>/.grasp-pipeline-<host>-<pid>.lock`` (JSON: pid, host,
process start, command, time) and looks at the other markers there: one whose process still
runs is another writer — a warning (logged and returned, for the report); one whose process is
gone (killed, crashed: it could not remove its marker) is stale and removed. A marker of another
host cannot be checked and counts as a writer. :meth:`OutputClaim.release` removes the claim's
own marker only (:func:`output_claim`: for a ``with`` block). The marker never stops a command: it warns.
"""

from __future__ import annotations

import json
import logging
import os
import socket
import time
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Iterator, Optional

log = logging.getLogger(__name__)

PREFIX = ".grasp-pipeline-"
SUFFIX = ".lock"


def _process_start(pid: int) -> Optional[str]:
    """The start time of process ``pid`` in clock ticks since boot (Linux), else None; with the
    pid it tells a live writer from a new process that reuses its pid."""
    try:
        with open(f"/proc/{pid}/stat", "rb") as fh:
            return fh.read().rsplit(b")", 1)[1].split()[19].decode()
    except (OSError, IndexError):
        return None


def _alive(info: dict) -> bool:
    """Whether the process that wrote marker ``info`` still runs (on this host)."""
    pid = info.get("pid")
    if not isinstance(pid, int) or pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's live process
        return True
    started = info.get("process_start")
    return started is None or _process_start(pid) in (None, started)


@dataclass
class OutputClaim:
    """This process's marker in ``folder`` and the warning about other writers ("" if none)."""

    folder: Path
    marker: Optional[Path]
    warning: str = ""

    def release(self) -> None:
        """Remove this claim's marker (never another process's)."""
        if self.marker is not None:
            try:
                self.marker.unlink()
            except OSError:
                pass
            self.marker = None


def _others(folder: Path, mine: Path) -> list[dict]:
    """The live writers' markers in ``folder``; stale ones are removed."""
    host = socket.gethostname()
    live = []
    for path in sorted(folder.glob(f"{PREFIX}*{SUFFIX}")):
        if path == mine:
            continue
        try:
            info = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            info = {}
        if not isinstance(info, dict):
            info = {}
        if info.get("host") not in (None, host) or _alive(info):
            live.append(info)
            continue
        log.info("removing the stale output marker %s (its process is gone)", path)
        try:
            path.unlink()
        except OSError:
            pass
    return live


def claim_output(folder: str | Path, command: str) -> OutputClaim:
    """Mark ``folder`` as written by this process (see the module doc); an OS error making the
    marker is logged and the command goes on unmarked."""
    folder = Path(folder)
    host, pid = socket.gethostname(), os.getpid()
    marker = folder / f"{PREFIX}{host}-{pid}{SUFFIX}"
    info = {"pid": pid, "host": host, "process_start": _process_start(pid), "command": command,
            "started": time.strftime("%Y-%m-%d %H:%M:%S")}
    try:
        folder.mkdir(parents=True, exist_ok=True)
        marker.write_text(json.dumps(info), encoding="utf-8")
    except OSError as exc:
        log.warning("cannot mark the output folder %s as in use (%s)", folder, exc)
        return OutputClaim(folder, None)
    others = _others(folder, marker)
    claim = OutputClaim(folder, marker)
    if others:
        who = "; ".join(f"pid {o.get('pid', '?')} on {o.get('host', '?')}, {o.get('command', '?')}, "
                        f"started {o.get('started', '?')}" for o in others)
        claim.warning = (f"another grasp-pipeline process is writing to {folder} ({who}): the two "
                         "commands' files mix there and the last report written wins; give each "
                         "command its own --out")
        log.warning("%s", claim.warning)
    return claim


@contextmanager
def output_claim(folder: str | Path, command: str, enabled: bool = True) -> Iterator[OutputClaim]:
    """:func:`claim_output` for the block, released at its end whatever happens (``enabled``
    False: no marker)."""
    claim = claim_output(folder, command) if enabled else OutputClaim(Path(folder), None)
    try:
        yield claim
    finally:
        claim.release()
