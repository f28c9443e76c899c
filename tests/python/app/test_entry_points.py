"""Every console entry point, run as a user runs it: the installed ``grasp-pipeline`` in a
subprocess with a clean environment (no PYTHONPATH, no exported variables), for
``MUJOCO_GL`` unset, ``egl``, ``osmesa`` and ``disable``. Each run must give a complete,
valid result — or a clear one-line error with a non-zero exit code — never an abort.

Small versions of each command keep this quick; the real parts run (MuJoCo, PCL, OMPL,
TOPP-RA). Without any GL (``disable``) the camera ray-casts and the video is skipped."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from grasp_pipeline.perception.synthetic import tabletop_frame

GL_SETTINGS = [None, "egl", "osmesa", "disable"]
EXE = Path(sys.executable).parent / "grasp-pipeline"
ONE_OBJECT = ["--set", "sim.object_count=[1,1]"]
TIMEOUT_S = 900



@pytest.fixture(autouse=True)
def installed_console_script():
    """These tests run the product as a user does: the console script ``pip install .``
    installs next to this interpreter (``make test`` does that first)."""
    assert EXE.exists(), f"{EXE} is missing: install the package first (make setup, or pip install .)"


def clean_env(gl: str | None, home: Path) -> dict:
    """What a plain shell gives: PATH and HOME (plus MUJOCO_GL when the case sets it)."""
    env = {"PATH": f"{EXE.parent}:/usr/local/bin:/usr/bin:/bin", "HOME": str(home), "LANG": "C.UTF-8"}
    if gl is not None:
        env["MUJOCO_GL"] = gl
    return env


def run_cli(args: list[str], gl: str | None, cwd: Path) -> subprocess.CompletedProcess:
    res = subprocess.run([str(EXE), *args], cwd=cwd, env=clean_env(gl, cwd), capture_output=True,
                         text=True, timeout=TIMEOUT_S, stdin=subprocess.DEVNULL)
    assert res.returncode >= 0, f"killed by signal {-res.returncode}\n{res.stderr[-3000:]}"
    assert res.returncode != 134 and "Traceback" not in res.stderr, res.stderr[-3000:]
    assert "libc++abi" not in res.stderr and "Segmentation fault" not in res.stderr, res.stderr[-3000:]
    return res


def strict_json(path: Path) -> dict:
    """RFC 8259: no NaN / Infinity."""
    def refuse(c):
        raise ValueError(f"{path} holds {c}")

    return json.loads(path.read_text(), parse_constant=refuse)


def gl_id(gl):
    return "unset" if gl is None else gl


@pytest.fixture
def work(tmp_path):
    return tmp_path


@pytest.mark.parametrize("gl", GL_SETTINGS, ids=gl_id)
def test_run_completes_and_writes_a_valid_report(gl, work):
    res = run_cli(["run", "--scene", "reference", "--select", "1.5", "1.5", "--no-scan",
                   "--out", "out"], gl, work)
    assert res.returncode == 1, res.stderr[-2000:]  # the far selection is refused
    report = strict_json(work / "out" / "report.json")
    assert report["status"] == "complete"
    assert len(report["rough"]["tracks"]) == 3
    assert report["picks"][0]["failed_stage"] == "SELECT"
    assert (work / "out" / "rough.png").stat().st_size > 10_000
    if gl == "disable":
        assert report["video"] is None and any("video skipped" in w for w in report["warnings"])
    else:
        assert (work / report["video"]).stat().st_size > 10_000


@pytest.mark.parametrize("gl", GL_SETTINGS, ids=gl_id)
def test_demo_picks_an_object(gl, work):
    res = run_cli(["demo", "--out", "demo", "--select", "0.56", "-0.03", "--no-scan", "--no-video"],
                  gl, work)
    report = strict_json(work / "demo" / "report.json")
    assert res.returncode == 0, report["picks"]
    assert report["picks"][0]["success"] and report["picks"][0]["placed"]
    assert "views:" not in res.stderr  # per-frame view lines are DEBUG


@pytest.mark.parametrize("gl", GL_SETTINGS, ids=gl_id)
def test_perceive_reads_a_cloud_file(gl, work):
    pts, _ = tabletop_frame(seed=3)
    np.save(work / "cloud.npy", pts)
    eye = " ".join(str(float(v)) for v in np.eye(4).reshape(-1))
    res = run_cli(["perceive", "cloud.npy", "--T-world-camera", eye, "--json", "p.json"], gl, work)
    assert res.returncode == 0, res.stderr[-2000:]
    assert len(strict_json(work / "p.json")["objects"]) == 3


@pytest.mark.parametrize("gl", GL_SETTINGS, ids=gl_id)
def test_bench_perception_without_the_optional_baseline(gl, work):
    res = run_cli(["bench", "perception", "--frames", "3", "--json", "b.json"], gl, work)
    assert res.returncode == 0, res.stderr[-2000:]
    out = strict_json(work / "b.json")
    assert out["median_ms"] > 0
    try:
        import open3d  # noqa: F401
    except ImportError:
        assert "pip install '.[bench]'" in out["baseline_note"]


@pytest.mark.parametrize("gl", GL_SETTINGS, ids=gl_id)
def test_bench_sim(gl, work):
    # (the pick-loop round is tested in tests/python/bench/test_sim_bench.py)
    res = run_cli(["bench", "sim", "--seconds", "0.2", "--json", "s.json", "--pick-scene", "none"], gl, work)
    assert res.returncode == 0, res.stderr[-2000:]
    assert strict_json(work / "s.json")["pick_loop"] is None


@pytest.mark.parametrize("gl", GL_SETTINGS, ids=gl_id)
def test_bench_planning(gl, work):
    res = run_cli(["bench", "planning", "--scenes", "1", "--seed", "4", "--json", "pl.json", *ONE_OBJECT],
                  gl, work)
    assert res.returncode == 0, res.stderr[-2000:]
    out = strict_json(work / "pl.json")
    assert out["plans"] >= 5 and out["robot_contacts_during_motion"] == 0
    # planning-thread CPU time next to the wall time (robust to a loaded machine)
    assert 0.0 < out["cpu_median_ms"] <= out["cpu_p90_ms"]
    assert all(v["cpu_median_ms"] is not None for v in out["by_kind"].values())


@pytest.mark.parametrize("gl", GL_SETTINGS, ids=gl_id)
def test_bench_grasp(gl, work):
    res = run_cli(["bench", "grasp", "--scenes", "1", "--seed", "5", "--workers", "1", "--json", "g.json",
                   "--out", "bg", "--no-progress", *ONE_OBJECT], gl, work)
    assert res.returncode == 0, res.stderr[-2000:]
    out = strict_json(work / "g.json")
    assert out["objects"] == 1 and not out["scenes_failed"]


@pytest.mark.parametrize("gl", GL_SETTINGS, ids=gl_id)
def test_bench_workers(gl, work):
    res = run_cli(["bench", "workers", "--scenes", "1", "--seed", "5", "--workers", "2", "--json", "w.json",
                   "--out", "bw", "--no-progress", *ONE_OBJECT], gl, work)
    assert res.returncode == 0, res.stderr[-2000:]
    assert strict_json(work / "w.json")["results_identical"]


@pytest.mark.parametrize("args, words", [
    (["run", "--select", "nan", "0"], "finite"),
    (["run", "--select", "0.5"], "pairs"),
    (["run", "--json", "/proc/no/such/report.json"], "report file"),
    (["run", "--set", "grasp.lift_hieght_m=0.1"], "unknown parameter"),
    (["bench", "perception", "--frames", "0", "--json", "x.json"], "whole number >= 1"),
    (["perceive", "missing.pcd", "--up", "0", "0", "1", "--json", "x.json"], "missing.pcd"),
    (["run", "--config", "."], "is a directory"),
    (["perceive", "x.npy", "--up", "0", "0", "1", "--json", "."], "is a directory"),
])
def test_bad_input_gives_a_one_line_error(args, words, work):
    res = run_cli(args, "disable", work)
    assert res.returncode != 0
    lines = [ln for ln in res.stderr.splitlines() if ln.strip()]
    errors = [ln for ln in lines if "error" in ln.lower()]
    assert errors and words in errors[-1], res.stderr[-2000:]


def test_perceive_workspace_options_drop_far_points_and_far_noise(work):
    """``--max-range-m`` and ``--crop`` on a real-capture-like floor cloud (near
    objects, far noise patches), run as a user runs them."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "core"))
    from real_capture_like import CAMERA, NEAR_BOXES, floor_capture

    np.save(work / "floor.npy", floor_capture() - CAMERA.astype(np.float32))  # camera frame
    T = np.eye(4)
    T[:3, 3] = CAMERA
    pose = " ".join(str(float(v)) for v in T.reshape(-1))
    res = run_cli(["perceive", "floor.npy", "--T-world-camera", pose, "--max-range-m", "1.5",
                   "--json", "near.json"], None, work)
    assert res.returncode == 0, res.stderr[-2000:]
    near = strict_json(work / "near.json")
    assert near["input"]["outside_workspace_points"] > 10_000
    assert near["settings"]["workspace"]["workspace_max_range_m"] == 1.5
    assert len(near["objects"]) == len(NEAR_BOXES)
    assert "outside it" in res.stdout
    res = run_cli(["perceive", "floor.npy", "--T-world-camera", pose, "--crop", "0.4", "0.7",
                   "-0.3", "0.3", "-0.1", "0.5", "--json", "crop.json"], None, work)
    assert res.returncode == 0, res.stderr[-2000:]
    crop = strict_json(work / "crop.json")
    assert crop["settings"]["workspace"]["workspace_crop_box_m"] == [0.4, 0.7, -0.3, 0.3, -0.1, 0.5]
    assert len(crop["objects"]) == len(NEAR_BOXES)
    bad = run_cli(["perceive", "floor.npy", "--T-world-camera", pose, "--crop", "1", "0", "0",
                   "1", "0", "1", "--json", "bad.json"], None, work)
    assert bad.returncode != 0 and "workspace_crop_box_m" in bad.stderr
