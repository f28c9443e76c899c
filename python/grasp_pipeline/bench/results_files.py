"""Writing a benchmark's results so that a signal cannot lose them: the JSON first, then the
plots and ``summary.md``, then the JSON again with them; Ctrl-C / SIGTERM while writing leaves
a JSON that says ``interrupted`` while writing (the plots or summary may be missing).

The result is a typed result (a frozen dataclass with the fields ``plots``, ``summary``,
``status`` and ``interrupted_while``, its long list of rows last); the plots and the summary
are drawn from its JSON form, as a results file holds it."""

from __future__ import annotations

import logging
from dataclasses import replace
from pathlib import Path
from typing import Callable, Optional, TypeVar

from ..report.serialize import to_jsonable, write_json

log = logging.getLogger(__name__)

R = TypeVar("R")
#: ``write_plots(result JSON, out) -> {name: path}``
PlotsWriter = Callable[[dict, Path], dict]
#: ``write_summary(result JSON, path, json_path=) -> path``
SummaryWriter = Callable[..., Path]


def write_results(result: R, out: Path, json_path: Optional[Path], write_plots: PlotsWriter,
                  write_summary: SummaryWriter) -> R:
    """Write ``result`` as above; returns it with ``plots`` (paths relative to ``out``) and
    ``summary`` set — or, interrupted while writing, with ``status`` interrupted."""
    try:
        if json_path is not None:
            write_json(json_path, result)
        plots = write_plots(to_jsonable(result), out)
        result = replace(result, plots={k: str(Path(v).relative_to(out)) for k, v in plots.items()})
        summary = write_summary(to_jsonable(result), out / "summary.md", json_path=json_path)
        result = replace(result, summary=str(summary))
        if json_path is not None:
            write_json(json_path, result)
    except KeyboardInterrupt:
        result = replace(result, status="interrupted", interrupted_while="writing the plots and summary")
        if json_path is not None:
            write_json(json_path, result)
        log.error("interrupted while writing the plots and summary; %s says so", json_path)
    return result
