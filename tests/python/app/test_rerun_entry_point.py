"""``grasp-pipeline run --rerun`` as a user runs it (the installed console script, a clean
environment), the recording read back with Rerun's own reader and checked against the
run's report; and the clear refusal when the Rerun SDK is missing."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from grasp_pipeline.report.rerun_summary import summarize_recording

EXE = Path(sys.executable).parent / "grasp-pipeline"
TIMEOUT_S = 900
STATE_RATE_HZ = 20.0  # config/rerun.yaml


def clean_env(home: Path) -> dict:
    return {"PATH": f"{EXE.parent}:/usr/local/bin:/usr/bin:/bin", "HOME": str(home), "LANG": "C.UTF-8"}


def run(args: list[str], cwd: Path) -> subprocess.CompletedProcess:
    res = subprocess.run(args, cwd=cwd, env=clean_env(cwd), capture_output=True, text=True,
                         timeout=TIMEOUT_S, stdin=subprocess.DEVNULL)
    assert "Traceback" not in res.stderr and res.returncode >= 0, res.stderr[-3000:]
    return res


@pytest.fixture(scope="module")
def one_object_run(tmp_path_factory):
    """One short simulated run (one object, no video) with a recording."""
    assert EXE.exists(), f"{EXE} is missing: install the package first (make setup)"
    work = tmp_path_factory.mktemp("rerun_run")
    res = run([str(EXE), "run", "--scene", "random", "--seed", "0", "--set", "sim.object_count=[1,1]",
               "--no-video", "--out", "out", "--rerun", "rec/run.rrd"], work)
    assert res.returncode in (0, 1), res.stderr[-3000:]
    report = json.loads((work / "out" / "report.json").read_text())
    return report, summarize_recording(work / "rec" / "run.rrd"), res.stdout, work


def test_the_run_reports_its_recording(one_object_run):
    report, _, stdout, work = one_object_run
    assert report["status"] == "complete" and report["recording"] == "rec/run.rrd"
    assert "rerun rec/run.rrd" in stdout
    assert (work / "rec" / "run.rrd").stat().st_size > 100_000


def test_clouds_and_camera_images_are_recorded_together(one_object_run):
    _, s, _, _ = one_object_run
    frames = s["/world/camera"].logs
    assert frames >= 3                                   # rough view, probe, scan end at least
    for e in ("/world/camera/image/rgb", "/world/camera/image/depth", "/world/cloud/objects",
              "/world/cloud/environment"):
        assert s[e].logs == frames and s[e].times_s == s["/world/camera"].times_s, e
    assert s["/world/camera/image"].static and s["/world/camera/image"].archetypes == ["Pinhole"]
    assert s["/world/cloud/objects"].largest > 100
    assert 1000 < s["/world/cloud/environment"].largest <= 20000
    assert s["/plots/perception_ms"].logs >= frames


def _latest_at(entity, t_s: float) -> int:
    k = int(np.searchsorted(np.asarray(entity.times_s), t_s + 1e-9)) - 1
    assert k >= 0
    return entity.batches[k]


def test_one_box_per_perceived_object(one_object_run):
    report, s, _, _ = one_object_run
    stages = s["/timeline/stages"]
    t_scan = stages.times_s[stages.texts.index("scan_done")]
    assert _latest_at(s["/world/objects"], t_scan) == len(report["scan"]["tracks"]) == 1
    assert s["/world/objects"].archetypes == ["Boxes3D"]


def test_stages_plans_and_grasps_are_on_the_timeline(one_object_run):
    report, s, _, _ = one_object_run
    texts = s["/timeline/stages"].texts
    for name in ("rough_view_done", "scan_done", "PRE_GRASP"):
        assert name in texts
    probes = [t for t in texts if t.startswith("probe_arrived")]
    assert len(probes) >= len(report["scan"]["probes"]) >= 1
    # every stage event is a log: the two views, and per started pick its start and stages
    started = [p for p in report["picks"] if p["stages"]]
    assert len(texts) - len(probes) == 2 + sum(1 + len(p["stages"]) for p in started)
    plans = len(report["motion_plans"])
    assert plans >= 5 and s["/timeline/plans"].logs == s["/world/paths/planned"].logs == plans
    reached = sum(any(st[0] == "PRE_GRASP" for st in p["stages"]) for p in report["picks"])
    assert reached >= 1 and s["/world/grasps/candidates"].logs == reached
    approached = sum(any(st[0] == "APPROACH" for st in p["stages"]) for p in report["picks"])
    assert approached <= s["/world/grasps/chosen"].logs <= reached   # planned, then moved
    assert s["/timeline/picks"].logs == len(report["picks"])


def test_tcp_paths_and_series_follow_simulated_time(one_object_run):
    report, s, _, _ = one_object_run
    sim_s = report["timings"]["run_sim_s"]
    assert abs(s["/world/tcp"].logs - sim_s * STATE_RATE_HZ) <= 2
    assert s["/plots/finger_gap_mm"].logs == s["/world/tcp"].logs
    assert s["/world/paths/executed"].last >= len(report["motion_plans"]) - 1


def test_the_planned_path_starts_where_the_tcp_is(one_object_run):
    """The planned path (forward kinematics of the trajectory) and the TCP the robot reports
    share one frame: each plan starts within 1 cm of the TCP sampled when it was planned."""
    import rerun.dataframe as rdf

    _, _, _, work = one_object_run
    rec = rdf.load_recording(str(work / "rec" / "run.rrd"))
    plans = rec.view(index="sim_time", contents="/world/paths/planned").select().read_all()
    tcp = rec.view(index="sim_time", contents="/world/tcp").select().read_all()
    t_tcp = np.asarray(tcp.column("sim_time").cast("int64").to_pylist()) * 1e-9
    p_tcp = np.array([v[0] for v in tcp.column("/world/tcp:Transform3D:translation").to_pylist()])
    t_plan = np.asarray(plans.column("sim_time").cast("int64").to_pylist()) * 1e-9
    for t, strips in zip(t_plan, plans.column("/world/paths/planned:LineStrips3D:strips").to_pylist()):
        k = int(np.argmin(np.abs(t_tcp - t)))
        assert np.linalg.norm(np.asarray(strips[0][0]) - p_tcp[k]) < 0.01, (t, strips[0][0], p_tcp[k])


def test_without_the_sdk_rerun_is_refused_before_the_simulation_starts(tmp_path):
    code = ("import sys; sys.modules['rerun'] = None; from grasp_pipeline.cli import main; "
            "sys.exit(main(['run', '--no-video', '--out', 'out', '--rerun', 'run.rrd']))")
    res = run([sys.executable, "-c", code], tmp_path)
    assert res.returncode == 2
    assert "pip install 'grasp-pipeline[rerun]'" in res.stderr
    assert not (tmp_path / "out" / "report.json").exists() and not (tmp_path / "run.rrd").exists()


def test_a_recording_path_that_is_not_rrd_is_refused(tmp_path):
    res = run([str(EXE), "run", "--no-video", "--out", "out", "--rerun", "run.mp4"], tmp_path)
    assert res.returncode == 2 and ".rrd" in res.stderr
