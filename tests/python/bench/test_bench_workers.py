"""The worker-scaling benchmark's pure parts (the full run is a benchmark, not a test)."""

import pytest

from grasp_pipeline.bench.grasp_result import differences
from grasp_pipeline.bench.workers_bench import run_workers_benchmark


def test_differences_lists_paths_of_changed_values():
    a = {"x": 1, "rows": [{"ok": True}, {"ok": False}], "same": "s"}
    b = {"x": 2, "rows": [{"ok": True}, {"ok": True}], "same": "s"}
    assert differences(a, b) == [".rows[1].ok: False != True", ".x: 1 != 2"]
    assert differences(a, a) == []


def test_differences_is_bounded():
    a = {str(i): i for i in range(50)}
    b = {str(i): -i - 1 for i in range(50)}
    assert len(differences(a, b, limit=5)) == 5


def test_one_worker_cannot_be_compared_with_itself(tmp_path):
    with pytest.raises(ValueError, match="workers must be >= 2"):
        run_workers_benchmark(scenes=1, workers=1, out_dir=tmp_path)
