"""``bench grasp --backend ray``: a 2-scene run through the installed console script (a local
Ray instance starts by itself) gives the same result as the local backend for the seed,
timings aside — each scene runs in a fresh worker process on both backends."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from grasp_pipeline.bench.grasp_result import differences, strip_timings

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from faults import EXE, clean_env  # noqa: E402
SEED, SCENES = 142, 2          # two one-object scenes (see test_bench_grasp)
RUN_DEPENDENT = ("backend", "plots", "summary", "workers_requested")


def _bench(backend: str, d: Path) -> dict:
    env = clean_env(d)  # (with PYTHONPATH when a source checkout is under test)
    res = subprocess.run([str(EXE), "--log-level", "WARNING", "bench", "grasp", "--scenes", str(SCENES),
                          "--seed", str(SEED), "--workers", "2", "--backend", backend,
                          "--json", "b.json", "--out", "out", "--no-progress"],
                         cwd=d, env=env, capture_output=True, text=True, timeout=1200,
                         stdin=subprocess.DEVNULL)
    assert res.returncode == 0 and "Traceback" not in res.stderr, res.stderr[-3000:]
    return json.loads((d / "b.json").read_text())


def test_ray_backend_gives_the_local_result(tmp_path):
    assert EXE.exists(), f"{EXE} is missing: install the package first (make setup)"
    (tmp_path / "local").mkdir()
    (tmp_path / "ray").mkdir()
    local = _bench("local", tmp_path / "local")
    ray = _bench("ray", tmp_path / "ray")
    assert ray["backend"] == "ray" and local["backend"] == "local"
    assert ray["scenes"] == SCENES and ray["scenes_failed"] == 0
    same = lambda r: strip_timings({k: v for k, v in r.items() if k not in RUN_DEPENDENT})  # noqa: E731
    assert differences(same(local), same(ray)) == []
