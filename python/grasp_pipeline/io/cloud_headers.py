"""Point counts of cloud files, checked from their headers before anything is read.

A header states how many points follow; a reader allocates for that many before it finds out
the file is shorter. A PLY claiming 10^9 vertices made PCL allocate 11.6 GB before refusing it.
:func:`check_cloud_header` reads only the header (at most :data:`MAX_HEADER_BYTES`) and refuses,
with an :class:`InputError` naming the file:

* more than :data:`MAX_CLOUD_POINTS` points (the largest camera frame, 4096 x 4096, is 16.8 M);
* more data than the file holds: binary PLY ``element`` counts times their smallest record,
  binary PCD ``POINTS`` times the record, a ``.npy`` shape times its item size (ASCII bodies
  are checked line by line by the reader before it allocates anything).

Headers this check does not understand are left to the reader (which names what is wrong).
"""

from __future__ import annotations

import os
from typing import Optional

import numpy as np

from ..exceptions import InputError

#: Most points a cloud file may hold (the largest camera frame, 4096 x 4096, is 16.8 M points).
MAX_CLOUD_POINTS = 20_000_000
#: Longest header read [bytes].
MAX_HEADER_BYTES = 65_536

#: Bytes of each PLY scalar type.
PLY_TYPE_BYTES = {"char": 1, "int8": 1, "uchar": 1, "uint8": 1, "short": 2, "int16": 2,
                  "ushort": 2, "uint16": 2, "int": 4, "int32": 4, "uint": 4, "uint32": 4,
                  "float": 4, "float32": 4, "double": 8, "float64": 8}


def _too_many(path: str, n: int, what: str) -> InputError:
    return InputError(f"{path}: the header declares {n} {what}; at most {MAX_CLOUD_POINTS} points "
                      "are read (split or downsample the cloud)")


def _short(path: str, n: int, what: str, need: int, have: int) -> InputError:
    return InputError(f"{path}: the header declares {n} {what} ({need} bytes at least) but the file "
                      f"holds {have} bytes after its header (truncated, or a wrong count)")


def _head(path: str) -> bytes:
    with open(path, "rb") as fh:
        return fh.read(MAX_HEADER_BYTES)


def _ply_elements(lines: list[str]) -> Optional[tuple[str, list]]:
    """(format, [(name, count, smallest record bytes)]) or None."""
    fmt, elements = None, []
    for line in lines[1:]:
        tok = line.split()
        if not tok or tok[0] in ("comment", "obj_info"):
            continue
        if tok[0] == "format" and len(tok) >= 2:
            fmt = tok[1]
        elif tok[0] == "element" and len(tok) == 3 and tok[2].lstrip("-").isdigit():
            elements.append([tok[1], int(tok[2]), 0])
        elif tok[0] == "property" and elements:
            kind = tok[2] if len(tok) == 5 and tok[1] == "list" else tok[1]
            if kind not in PLY_TYPE_BYTES:
                return None
            elements[-1][2] += PLY_TYPE_BYTES[kind]  # a list: its length at least
        else:
            return None
    return (fmt, elements) if fmt else None


def check_ply_header(path: str) -> None:
    head = _head(path)
    end = head.find(b"end_header")
    if not head.startswith(b"ply") or end < 0:
        return
    nl = head.find(b"\n", end)
    parsed = _ply_elements(head[:end].decode("ascii", "replace").splitlines())
    if parsed is None or nl < 0:
        return
    fmt, elements = parsed
    have = os.path.getsize(path) - (nl + 1)
    for name, count, _ in elements:
        if name == "vertex" and count > MAX_CLOUD_POINTS:
            raise _too_many(path, count, "vertices")
    if fmt == "ascii":  # read line by line before anything is allocated (the reader's own check)
        return
    need = sum(count * record for _, count, record in elements)
    if need > max(have, 0):
        total = sum(count for _, count, _ in elements)
        raise _short(path, total, "element instances (vertices, faces ...)", need, have)


def _pcd_header(head: bytes) -> Optional[tuple[dict, int]]:
    """({key: tokens}, offset of the data) of a PCD header, or None."""
    fields, pos = {}, 0
    while pos < len(head):
        nl = head.find(b"\n", pos)
        if nl < 0:
            return None
        tok = head[pos:nl].decode("ascii", "replace").split()
        pos = nl + 1
        if tok and not tok[0].startswith("#"):
            fields[tok[0].upper()] = tok[1:]
            if tok[0].upper() == "DATA":
                return fields, pos
    return None


def _int(tokens: list, default: Optional[int] = None) -> Optional[int]:
    try:
        return int(tokens[0])
    except (IndexError, ValueError, TypeError):
        return default


def check_pcd_header(path: str) -> None:
    parsed = _pcd_header(_head(path))
    if parsed is None:
        return
    h, data_at = parsed
    points = _int(h.get("POINTS", []))
    if points is None:
        width, height = _int(h.get("WIDTH", [])), _int(h.get("HEIGHT", []), 1)
        points = None if width is None or height is None else width * height
    if points is None or points < 0:
        return
    if points > MAX_CLOUD_POINTS:
        raise _too_many(path, points, "points")
    try:
        sizes = [int(v) for v in h.get("SIZE", [])]
        counts = [int(v) for v in h.get("COUNT", [])] or [1] * len(sizes)
    except ValueError:
        return
    record = sum(s * c for s, c in zip(sizes, counts))
    encoding = (h.get("DATA") or [""])[0]
    have = os.path.getsize(path) - data_at
    need = points * record if encoding == "binary" else 0  # ascii: checked line by line
    if need > have:
        raise _short(path, points, "points", need, have)


def check_npy_header(path: str) -> None:
    readers = {(1, 0): np.lib.format.read_array_header_1_0, (2, 0): np.lib.format.read_array_header_2_0}
    try:
        with open(path, "rb") as fh:
            shape, _, dtype = readers[np.lib.format.read_magic(fh)](fh)
            data_at = fh.tell()
    except Exception:  # not a .npy header (or a version read elsewhere): numpy's reader says
        return
    n = int(np.prod(shape, dtype=object)) if shape else 1
    rows = n // 3 if n else 0
    if rows > MAX_CLOUD_POINTS:
        raise _too_many(path, rows, "points (shape " + "x".join(map(str, shape)) + ")")
    need, have = n * dtype.itemsize, os.path.getsize(path) - data_at
    if need > have:
        raise _short(path, rows, "points", need, have)


def check_cloud_header(path: str, ext: str) -> None:
    """Refuse (InputError) a cloud file whose header declares too many points or more data than
    it holds; ``ext``: ``.ply``, ``.pcd`` or ``.npy``."""
    if not os.path.isfile(path):
        return  # the reader names a missing file
    {".ply": check_ply_header, ".pcd": check_pcd_header, ".npy": check_npy_header}[ext](path)
