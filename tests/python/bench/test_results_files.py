"""Writing a benchmark's results (bench/results_files.py): the JSON, the plots and the summary;
interrupted while writing, a JSON that says so."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

from grasp_pipeline.bench.results_files import write_results
from grasp_pipeline.report.serialize import OMIT_IF_NONE


@dataclass(frozen=True)
class _Result:
    status: str = "complete"
    interrupted_while: Optional[str] = field(default=None, metadata=OMIT_IF_NONE)
    plots: Optional[dict] = field(default=None, metadata=OMIT_IF_NONE)
    summary: Optional[str] = None
    rows: tuple = ({"index": 0},)


def _plots(result: dict, out: Path) -> dict:
    assert result["rows"] == [{"index": 0}]  # (drawn from the JSON form)
    (out / "a.png").write_bytes(b"png")
    return {"a": out / "a.png"}


def _summary(result: dict, path: Path, json_path=None) -> Path:
    path.write_text(f"plots: {result['plots']}")
    return path


def test_the_json_names_the_plots_and_the_summary_and_keeps_the_rows_last(tmp_path):
    res = write_results(_Result(), tmp_path, tmp_path / "r.json", _plots, _summary)
    assert res.plots == {"a": "a.png"} and res.summary == str(tmp_path / "summary.md")
    data = json.loads((tmp_path / "r.json").read_text())
    assert list(data) == ["status", "plots", "summary", "rows"] and data["status"] == "complete"
    assert (tmp_path / "summary.md").read_text() == "plots: {'a': 'a.png'}"


def test_interrupted_while_plotting_the_json_says_so(tmp_path):
    def interrupted(result, out):
        raise KeyboardInterrupt

    res = write_results(_Result(), tmp_path, tmp_path / "r.json", interrupted, _summary)
    assert res.status == "interrupted" and res.interrupted_while == "writing the plots and summary"
    data = json.loads((tmp_path / "r.json").read_text())
    assert data == {"status": "interrupted", "interrupted_while": "writing the plots and summary",
                    "summary": None, "rows": [{"index": 0}]}
