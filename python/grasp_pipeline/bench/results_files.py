"""Writing a benchmark's results so that a signal cannot lose them: the JSON first, then the
plots and ``summary.md``, then the JSON again with them; Ctrl-C / SIGTERM while writing leaves
a JSON that says ``interrupted`` while writing (the plots or summary may be missing)."""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Callable, Optional

from ..report.serialize import write_json

log = logging.getLogger(__name__)


def write_results(result: dict, out: Path, json_path: Optional[Path], write_plots: Callable,
                  write_summary: Callable, rows_key: str) -> None:
    """``result`` (its ``rows_key`` list kept last: the long part) as above; ``write_plots(result,
    out)`` -> {name: path}, ``write_summary(result, path, json_path=)`` -> path."""
    result[rows_key] = result.pop(rows_key)
    try:
        if json_path is not None:
            write_json(json_path, result)
        result["plots"] = {k: str(Path(v).relative_to(out)) for k, v in write_plots(result, out).items()}
        result["summary"] = str(write_summary(result, out / "summary.md", json_path=json_path))
        result[rows_key] = result.pop(rows_key)
        if json_path is not None:
            write_json(json_path, result)
    except KeyboardInterrupt:
        result.update(status="interrupted", interrupted_while="writing the plots and summary")
        result.setdefault("summary", None)
        if json_path is not None:
            write_json(json_path, result)
        log.error("interrupted while writing the plots and summary; %s says so", json_path)
