"""The one JSON serializer of every result the product writes (run, perceive, benchmarks).

* :func:`to_jsonable` turns typed results (dataclasses, enums, numpy arrays and scalars,
  tuples, paths) into plain JSON values; non-finite floats become ``null`` — the output is
  valid JSON (RFC 8259 has no NaN or Infinity). A dataclass gives its fields in declaration
  order, less those named ``_...`` and those declared with :data:`OMIT_IF_NONE` while None
  (a key only some results have, e.g. ``interrupted_while``).
* :func:`write_json` writes atomically: a temporary file in the target folder, flushed, then
  renamed over the target, so an interrupted or failing write never leaves a truncated or
  empty file in place of a good one. Errors name the path (:class:`OutputError`).
"""

from __future__ import annotations

import dataclasses
import enum
import json
import math
import os
import secrets
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

from ..exceptions import GraspPipelineError


class OutputError(GraspPipelineError, OSError):
    """An output file or folder cannot be written (the message names the path)."""


#: Dataclass field metadata (``field(default=None, metadata=OMIT_IF_NONE)``): the key is left
#: out of the JSON while the value is None.
OMIT_IF_NONE = {"omit_if_none": True}


def _dataclass_items(obj: Any):
    """(name, value) of the fields of dataclass ``obj`` that the JSON holds."""
    for f in dataclasses.fields(obj):
        value = getattr(obj, f.name)
        if f.name.startswith("_") or (value is None and f.metadata.get("omit_if_none")):
            continue
        yield f.name, value


def to_jsonable(obj: Any) -> Any:
    """Plain JSON value of ``obj`` (see the module doc)."""
    if obj is None or isinstance(obj, (bool, str)):
        return obj
    if isinstance(obj, (int, np.integer)) and not isinstance(obj, bool):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        f = float(obj)
        return f if math.isfinite(f) else None
    if isinstance(obj, np.bool_):
        return bool(obj)
    if isinstance(obj, enum.Enum):
        return to_jsonable(obj.value)
    if isinstance(obj, np.ndarray):
        return to_jsonable(obj.tolist())
    if isinstance(obj, Path):
        return str(obj)
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return {name: to_jsonable(value) for name, value in _dataclass_items(obj)}
    if isinstance(obj, dict):
        return {str(k): to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple, set, frozenset)):
        return [to_jsonable(v) for v in obj]
    return str(obj)


def dumps(obj: Any, indent: int | None = 2, sort_keys: bool = False) -> str:
    """JSON text of ``obj`` (strict: no NaN/Infinity)."""
    return json.dumps(to_jsonable(obj), indent=indent, sort_keys=sort_keys, allow_nan=False)


def check_writable(path: str | Path, what: str = "output file") -> Path:
    """Fail early (before any work) when ``path`` cannot be written: creates its folder and
    checks that a file can be made there; an existing file is left untouched."""
    p = Path(path)
    if p.exists() and p.is_dir():
        raise OutputError(f"{what} {p} is a directory; give a file path")
    try:
        p.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{p.name}.", suffix=".check", dir=p.parent)
        os.close(fd)
        os.unlink(tmp)
    except OSError as exc:
        raise OutputError(f"cannot write the {what} {p}: {exc.strerror or exc}") from None
    return p


def check_writable_dir(path: str | Path, what: str = "output folder") -> Path:
    """Fail early when folder ``path`` cannot be created or written."""
    p = Path(path)
    if p.exists() and not p.is_dir():
        raise OutputError(f"{what} {p} exists and is not a folder")
    try:
        check_writable(p / ".write_check", what)
    except OutputError as exc:
        reason = str(exc).rsplit(": ", 1)[-1]
        raise OutputError(f"cannot write the {what} {p}: {reason}") from None
    return p


def _new_temporary(p: Path) -> tuple[int, str]:
    """A new temporary file next to ``p`` (open for writing), with the permissions of any new
    file: 0666 less the umask, as the PNGs and videos beside it (``tempfile.mkstemp`` makes it
    0600, and the report renamed from it could be read by its owner only)."""
    for _ in range(100):
        tmp = p.parent / f".{p.name}.{os.getpid()}-{secrets.token_hex(4)}.tmp"
        try:
            return os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666), str(tmp)
        except FileExistsError:
            continue
    raise FileExistsError(f"no free temporary name next to {p}")


def write_json(path: str | Path, obj: Any, sort_keys: bool = False) -> Path:
    """Write ``obj`` as strict JSON to ``path`` atomically; returns the path."""
    p = Path(path)
    text = dumps(obj, sort_keys=sort_keys)
    tmp = None
    try:
        p.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = _new_temporary(p)
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
            fh.write("\n")
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, p)
        tmp = None
    except OSError as exc:
        raise OutputError(f"cannot write {p}: {exc.strerror or exc}") from None
    finally:
        if tmp is not None and os.path.exists(tmp):
            os.unlink(tmp)
    return p
