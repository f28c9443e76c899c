"""The states of ``record``'s output folder on disk, so that an interrupted run never leaves a
half-written dataset.

``--out`` is, at any moment, one of:

* absent (or the empty folder it was): before anything was recorded;
* **marked incomplete**: the folder holds only :data:`MARKER` (``RECORD_INCOMPLETE.json``:
  the phase, why, how many episodes are finished and where they are kept) — while recording,
  and after a run that was stopped while writing or that finished no episode;
* **a complete LeRobot dataset** (with ``meta/grasp_pipeline_record.json`` saying whether the
  run completed or was interrupted and wrote the episodes finished until then).

The dataset is merged into a staging folder next to ``--out`` (:func:`staging_dir`) and only
then moved in (:func:`publish`: the marker is removed and the staging folder renamed onto the
then empty ``--out``, one rename), so ``--out`` never holds part of a dataset. The finished
episodes (shards) stay in the work folder (:func:`work_dir`) until the dataset is in place.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

from ..report.serialize import write_json

MARKER = "RECORD_INCOMPLETE.json"


def work_dir(out: Path) -> Path:
    """Where the workers write the finished episodes (next to ``out``)."""
    return out.parent / f".{out.name}.episodes"


def staging_dir(out: Path) -> Path:
    """Where the dataset is merged before it is moved to ``out``."""
    return out.parent / f".{out.name}.writing"


def mark_incomplete(out: Path, phase: str, reason: str, **details) -> Path:
    """Write (atomically) the marker of an incomplete ``out`` (the folder is created)."""
    out.mkdir(parents=True, exist_ok=True)
    return write_json(out / MARKER, {"status": "incomplete", "phase": phase, "reason": reason,
                                     **details})


def is_marked(out: Path) -> bool:
    return (out / MARKER).is_file()


def publish(staging: Path, out: Path) -> None:
    """Move the finished dataset ``staging`` to ``out`` (which holds at most the marker)."""
    marker = out / MARKER
    if marker.exists():
        marker.unlink()
    os.rename(staging, out)  # replaces the now empty folder (a folder with files is never replaced)


def discard(path: Path) -> None:
    shutil.rmtree(path, ignore_errors=True)
