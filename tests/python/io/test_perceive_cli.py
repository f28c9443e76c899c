"""``grasp-pipeline perceive``: a real cloud file through the scene filter and the estimates.

End-to-end: a synthetic organized 640x480 frame (ray-cast tabletop, method.md §8's reference
arrangement) saved as a binary_compressed PCD in *camera* coordinates, run through the CLI
with --T-world-camera and with --up.
"""

from __future__ import annotations

import json
import logging
import re

import numpy as np
import pytest

from grasp_pipeline.cli import main
from grasp_pipeline.exceptions import InputError
from grasp_pipeline.io import load_cloud, save_pcd
from grasp_pipeline.perceive import parse_transform, world_from_up
from grasp_pipeline.perception.synthetic import (Box, reference_camera_pose, reference_tabletop,
                                                 render_depth)

SCENE = reference_tabletop()


def true_centres() -> np.ndarray:
    out = []
    for obj in SCENE.objects:
        h = obj.size_m[2] if isinstance(obj, Box) else obj.height_m
        out.append([obj.center_xy[0], obj.center_xy[1], obj.base_z_m + h / 2.0])
    return np.array(out)


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    T = reference_camera_pose()
    pts_world, pts_cam = render_depth(SCENE, T, rng=np.random.default_rng(7))
    pts_cam = pts_cam.copy()
    pts_cam[:640 * 3] = np.nan  # a few invalid rows, as a real sensor delivers
    d = tmp_path_factory.mktemp("perceive")
    pcd = d / "tabletop_camera.pcd"
    save_pcd(pcd, pts_cam, width=640, height=480, encoding="binary_compressed")
    assert b"DATA binary_compressed" in pcd.read_bytes()[:400]
    return {"T": T, "pcd": pcd, "dir": d, "pts_world": pts_world}


def run(args, caplog=None):
    if caplog is not None:
        caplog.set_level(logging.INFO)
    return main(["perceive", *map(str, args)])


def test_perceive_with_T_world_camera_finds_table_and_objects(scene, capsys):
    js, png = scene["dir"] / "t.json", scene["dir"] / "t.png"
    rc = run([scene["pcd"], "--T-world-camera", *[f"{v:.12g}" for v in scene["T"].ravel()],
              "--json", js, "--png", png])
    assert rc == 0
    rep = json.loads(js.read_text())
    assert rep["input"]["points"] == 640 * 480
    assert rep["input"]["invalid_points"] == 640 * 3
    assert rep["input"]["organized"] == [480, 640]
    assert rep["plane"]["height_m"] == pytest.approx(0.200, abs=0.001)
    assert rep["plane"]["normal"][2] > 0.9999
    assert rep["plane"]["c"] == pytest.approx(-0.200, abs=0.001)
    objs = rep["objects"]
    assert len(objs) == 3
    centres = np.array([o["center"] for o in objs])
    for truth in true_centres():
        assert np.min(np.linalg.norm(centres - truth, axis=1)) < 0.005
    for o in objs:
        assert set(o) >= {"center", "extents", "theta_deg", "grasp_ok", "notes", "view",
                          "pca_tilt_deg", "num_points"}
        assert o["grasp_ok"] is True and o["notes"] == []
        assert o["view"]["quality"] == "oblique"  # seen from the oblique start pose
        assert 0.045 < o["extents"][0] < 0.06 and o["num_points"] > 500
    assert png.stat().st_size > 10_000
    out = capsys.readouterr().out
    m = re.search(r"table plane: .*height = ([-0-9.]+) m", out)
    assert m and float(m.group(1)) == pytest.approx(0.2, abs=0.001)
    assert re.search(r"#2 oblique +centre", out)


def test_perceive_with_up_vector(scene):
    R = scene["T"][:3, :3]
    up = R.T @ np.array([0.0, 0.0, 1.0])  # world +z seen from the camera
    js = scene["dir"] / "up.json"
    rc = run([scene["pcd"], "--up", *[f"{v:.9f}" for v in up], "--json", js])
    assert rc == 0
    rep = json.loads(js.read_text())
    T = np.array(rep["world_frame"]["T_world_camera"])
    n_cam = T[:3, :3].T @ np.array(rep["plane"]["normal"])  # the table normal in camera coords
    assert np.degrees(np.arccos(np.clip(n_cam @ up, -1, 1))) < 0.5
    # origin at the camera: the table is 0.56 - 0.2 = 0.36 m below it
    assert rep["plane"]["height_m"] == pytest.approx(-0.36, abs=0.002)
    assert len(rep["objects"]) == 3
    for o in rep["objects"]:
        assert o["extents"][0] == pytest.approx(0.05, abs=0.006)
        assert o["grasp_ok"]


def test_perceive_npy_world_cloud_identity_transform(scene):
    npy = scene["dir"] / "world.npy"
    np.save(npy, scene["pts_world"].reshape(480, 640, 3))
    js = scene["dir"] / "npy.json"
    eye = np.eye(4).ravel()
    assert run([npy, "--T-world-camera", ",".join(f"{v:g}" for v in eye), "--json", js]) == 0
    rep = json.loads(js.read_text())
    assert rep["input"]["format"] == "npy" and rep["input"]["organized"] == [480, 640]
    assert rep["plane"]["height_m"] == pytest.approx(0.2, abs=0.001)
    assert len(rep["objects"]) == 3


@pytest.mark.parametrize("values, needle", [
    (["1", "0", "0", "0"] * 3 + ["0", "0", "0"], "expected 16 numbers"),            # 15 numbers
    ([str(v) for v in np.diag([2.0, 2.0, 2.0, 1.0]).ravel()], "not orthonormal"),  # a scale
    ([str(v) for v in np.diag([1.0, 1.0, -1.0, 1.0]).ravel()], "det = -1"),          # a mirror
    ([str(v) for v in np.vstack([np.eye(4)[:3], [0, 0, 1, 1]]).ravel()], "last row"),
    (["a"] * 16, "not a number"),
])
def test_bad_transform_is_a_clear_error(scene, caplog, values, needle):
    rc = run([scene["pcd"], "--T-world-camera", *values, "--json", scene["dir"] / "bad.json"],
             caplog)
    assert rc == 2
    assert needle in caplog.text and "--T-world-camera" in caplog.text


def test_parse_transform_accepts_rounded_rotation():
    T = reference_camera_pose()
    rounded = [f"{v:.4f}" for v in T.ravel()]
    Tp = parse_transform(rounded)
    np.testing.assert_allclose(Tp, T, atol=2e-4)
    np.testing.assert_allclose(Tp[:3, :3].T @ Tp[:3, :3], np.eye(3), atol=1e-12)


def test_world_from_up_is_right_handed_and_deterministic():
    for up in ([0, -0.64, -0.77], [0, 0, 1], [1, 0, 0], [0.3, -2, 5]):
        T = world_from_up(up)
        R = T[:3, :3]
        np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-12)
        assert np.linalg.det(R) == pytest.approx(1.0)
        np.testing.assert_allclose(R[2], np.asarray(up) / np.linalg.norm(up), atol=1e-12)
        np.testing.assert_array_equal(T[:3, 3], 0.0)
    # x = the camera x axis projected (here already perpendicular to up)
    np.testing.assert_allclose(world_from_up([0, -0.64, -0.77])[0, :3], [1, 0, 0], atol=1e-12)
    with pytest.raises(InputError, match="zero"):
        world_from_up([0, 0, 0])


def test_wrong_up_vector_reports_no_table_plane(scene, caplog):
    rc = run([scene["pcd"], "--up", "1", "0", "0", "--json", scene["dir"] / "noplane.json"], caplog)
    assert rc == 2
    assert "no table plane found" in caplog.text
    assert "--up" in caplog.text and "metres" in caplog.text
    assert not (scene["dir"] / "noplane.json").exists()


def test_millimetre_cloud_hint(tmp_path, caplog):
    T = reference_camera_pose()
    _, pts_cam = render_depth(SCENE, T)
    np.save(tmp_path / "mm.npy", pts_cam[::4] * 1000.0)
    rc = run([tmp_path / "mm.npy", "--up", *(T[:3, :3].T @ [0, 0, 1]), "--json",
              tmp_path / "mm.json"], caplog)
    assert rc == 2
    assert "millimetres?" in caplog.text


def test_set_overrides_are_validated(scene, caplog):
    base = [scene["pcd"], "--up", "0", "-0.64", "-0.77", "--json", scene["dir"] / "s.json"]
    assert run(base + ["--set", "cluster_eps=-1"], caplog) == 2
    assert "cluster_eps" in caplog.text
    caplog.clear()
    assert run(base + ["--set", "nonsense=1"], caplog) == 2
    assert "nonsense" in caplog.text and "unknown parameter" in caplog.text


def test_set_and_config_change_the_result(scene, tmp_path):
    # A minimum cluster size above every object's point count: nothing left to estimate.
    cfg = tmp_path / "cfg.yaml"
    cfg.write_text("scene_filter:\n  cluster_min_points: 1000000\n")
    js = tmp_path / "c.json"
    up = reference_camera_pose()[:3, :3].T @ [0, 0, 1]
    assert run([scene["pcd"], "--up", *up, "--json", js, "--config", cfg]) == 0
    rep = json.loads(js.read_text())
    assert rep["objects"] == [] and rep["settings"]["scene_filter"]["cluster_min_points"] == 1000000
    assert run([scene["pcd"], "--up", *up, "--json", js, "--config", cfg,
                "--set", "cluster_min_points=20"]) == 0
    assert len(json.loads(js.read_text())["objects"]) == 3


def test_missing_file_is_a_clear_error(tmp_path, caplog):
    rc = run([tmp_path / "none.pcd", "--up", "0", "0", "1", "--json", tmp_path / "x.json"], caplog)
    assert rc == 2 and "not found" in caplog.text


def test_load_cloud_sees_the_saved_camera_frame(scene):
    cloud = load_cloud(scene["pcd"])
    assert cloud.shape_hw == (480, 640) and cloud.num_invalid == 640 * 3


@pytest.mark.parametrize("argv", [["--log-level", "WARNING", "run", "--seed", "3"],
                                  ["run", "--log-level", "WARNING", "--seed", "3"],
                                  ["run", "--seed", "3", "--log-level", "WARNING"]])
def test_log_level_before_or_after_the_sub_command(argv):
    from grasp_pipeline.cli import _split_log_level, build_parser

    level, rest = _split_log_level(argv)
    assert level == "WARNING"
    args = build_parser().parse_args(rest)
    assert (args.command, args.seed) == ("run", 3)


def test_bad_log_level_is_refused():
    from grasp_pipeline.cli import _split_log_level

    with pytest.raises(SystemExit):
        _split_log_level(["--log-level", "LOUD", "run"])


def test_perceive_binary_pcd_with_rows_at_float_max(scene, tmp_path):
    """Regression: >= 16 identical rows at ~3.4e38 in a binary PCD aborted `perceive` inside
    FLANN (kdtree_single_index.h assertion). They are dropped like NaN rows now (scene filter
    max_abs_coordinate_m). Run in a child interpreter: before the fix it killed the process."""
    import os
    import subprocess
    import sys

    pts = np.vstack([scene["pts_world"], np.full((40, 3), np.finfo(np.float32).max, np.float32)])
    pcd, js = tmp_path / "absurd.pcd", tmp_path / "absurd.json"
    save_pcd(pcd, pts, encoding="binary")
    eye = ",".join(f"{v:g}" for v in np.eye(4).ravel())
    code = ("import sys; from grasp_pipeline.cli import main; "
            f"sys.exit(main(['perceive', {str(pcd)!r}, '--T-world-camera', {eye!r}, '--json', {str(js)!r}]))")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p))
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=180,
                         env=env)
    assert res.returncode == 0, f"rc {res.returncode}\n{res.stderr[-2000:]}"
    rep = json.loads(js.read_text())
    assert len(rep["objects"]) == 3
    assert rep["plane"]["height_m"] == pytest.approx(0.2, abs=0.001)
