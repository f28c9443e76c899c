"""What a Rerun recording holds, read back with Rerun's own reader (``rerun.dataframe``).

:func:`summarize_recording` lists every entity of an ``.rrd`` file with how many times it
was logged (static entities: once; samples sent as columns: one per simulated time), the largest batch of one
log (points of a cloud, boxes of a frame, strips of a path) and the batch of its last log.
Tests use it to check a recording; it also answers "what is in this file" without a viewer.
Entities that only hold ``Clear`` logs are left out (the dataframe reader returns no rows for
them; a clear shows as an empty log of the entity it cleared).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from pathlib import Path

from .rerun_recorder import TIMELINE, import_rerun

#: Components that carry an entity's batch (the first one present counts).
#: Rerun's own sequence timeline: one value per log call.
LOG_TICK = "log_tick"
_BATCH_COMPONENTS = ("positions", "centers", "strips", "origins", "translation", "scalars", "text",
                     "blob", "buffer", "image_from_camera", "xyz")


@dataclass
class EntitySummary:
    """One entity: ``logs`` (non-empty logs on the timeline; 1 for static data), ``static``,
    ``largest`` and ``last`` batch sizes, ``archetypes`` (e.g. ``["Points3D"]``), and per
    non-empty log its simulated time [s] (``times_s``), batch size (``batches``) and, for
    text logs, the text (``texts``)."""

    path: str
    archetypes: list = field(default_factory=list)
    static: bool = False
    logs: int = 0
    largest: int = 0
    last: int = 0
    times_s: list = field(default_factory=list)
    batches: list = field(default_factory=list)
    texts: list = field(default_factory=list)


def _batch_column(components: list[str]) -> str:
    for name in _BATCH_COMPONENTS:
        for c in components:
            if c.split(":")[-1] == name:
                return c
    return components[0]


def _summarize_entity(recording, path: str, components: list[str]) -> EntitySummary:
    col = _batch_column(components)
    out = EntitySummary(path, sorted({c.split(":")[0] for c in components}))
    with warnings.catch_warnings():  # "static data only" is an answer here, not a problem
        warnings.simplefilter("ignore")
        # one row per log call (several logs at one simulated time stay apart); data sent
        # as columns has no log tick: one row per simulated time then
        table = recording.view(index=LOG_TICK, contents=path).select().read_all()
        if table.num_rows == 0:
            view = recording.view(index=TIMELINE, contents=path)
            table = view.select().read_all()
            if table.num_rows == 0:
                table, out.static = view.select_static().read_all(), True
    name = f"{path}:{col}"
    if name not in table.column_names:
        return out
    values = table.column(name).to_pylist()
    times = [None] * len(values) if out.static else \
        table.column(TIMELINE).cast("int64").to_pylist()  # nanoseconds
    for value, t in zip(values, times):
        n = len(value) if isinstance(value, list) else int(value is not None)
        if n:  # a Clear leaves empty rows
            out.logs += 1
            out.largest = max(out.largest, n)
            out.last = n
            out.batches.append(n)
            if t is not None:
                out.times_s.append(float(t) * 1e-9)
            if col.endswith(":text"):
                out.texts.append(value[0] if isinstance(value, list) else value)
    return out


def summarize_recording(path) -> dict[str, EntitySummary]:
    """Entity path (``/world/objects``) → :class:`EntitySummary`, for every entity of the
    ``.rrd`` file ``path`` (Rerun's own properties left out)."""
    import_rerun()
    import rerun.dataframe as rdf

    recording = rdf.load_recording(str(Path(path)))
    components: dict[str, list[str]] = {}
    for c in recording.schema().component_columns():
        if not c.entity_path.startswith("/__") and not c.component.startswith("Clear:"):
            components.setdefault(c.entity_path, []).append(c.component)
    return {p: _summarize_entity(recording, p, comps) for p, comps in sorted(components.items())}


def format_summary(summary: dict[str, EntitySummary]) -> str:
    """One line per entity: path, archetypes, logs, largest and last batch."""
    lines = []
    for s in summary.values():
        when = "static" if s.static else f"{s.logs} logs"
        lines.append(f"{s.path:32s} {','.join(s.archetypes):28s} {when:10s} largest {s.largest:6d}  last {s.last}")
    return "\n".join(lines)
