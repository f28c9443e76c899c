"""End-to-end on the reference scene (method.md §8) with the real parts: MuJoCo physics and
rendering, the PCL core, OMPL, TOPP-RA. No mocks. One run serves several assertions."""

import pytest

from grasp_pipeline.app.run import run_pipeline

BLUE_CUBE = (0.56, -0.03)
CYLINDER = (0.52, 0.09)
NOWHERE = (1.5, 1.5)


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    out = tmp_path_factory.mktemp("run")
    return run_pipeline(scene="reference", select=[BLUE_CUBE, CYLINDER, NOWHERE], out_dir=out,
                        json_path=out / "report.json", video=True).to_dict()


def test_table_plane_locks_at_the_reference_height(report):
    assert abs(report["plane"]["height_m"] - 0.200) < 0.001


def test_rough_view_sees_all_three_objects_obliquely(report):
    tracks = report["rough"]["tracks"]
    assert len(tracks) == 3
    assert all(t["quality"] == "OBLIQUE" for t in tracks)
    assert max(t["pca_tilt_deg"] for t in tracks) > 10.0  # oblique views tilt the PCA box


def test_scan_brings_every_object_to_nadir_and_returns_to_start(report):
    scan = report["scan"]
    assert scan["trigger"] == "scan started: probing 3 objects"
    assert scan["completed"], scan["failure"]
    tracks = scan["tracks"]
    assert len(tracks) == 3
    assert all(t["quality"] == "NADIR" for t in tracks)
    assert all(t["pca_tilt_deg"] < 1.0 for t in tracks)
    assert scan["returned_to_start"] and scan["joint_error_rad"] < 1e-3


def test_nadir_estimates_match_the_truth(report):
    for row in report["scan"]["scores"]:
        assert row["center_err_mm"] < 3.0, row
        assert row["width_err_mm"] < 2.0, row
        assert row["height_err_mm"] < 2.0, row


@pytest.mark.parametrize("index, name", [(0, "blue_cube"), (1, "green_cylinder")])
def test_selected_object_is_lifted_held_and_placed(report, index, name):
    pick = report["picks"][index]
    assert pick["success"], pick["message"]
    assert pick["object"] == name
    assert pick["lift_m"] >= 0.05
    assert pick["held_s"] >= 2.0
    assert pick["placed"]
    assert [s for s, _ in pick["stages"]][:5] == ["PRE_GRASP", "APPROACH", "CLOSE", "LIFT", "DONE"]


def test_selecting_far_from_any_object_is_refused_with_a_message(report):
    pick = report["picks"][2]
    assert not pick["success"] and pick["failed_stage"] == "SELECT"
    assert pick["message"].startswith("no object near (1.500, 1.500):")
    assert "mm away, limit" in pick["message"]


def test_run_writes_snapshots_and_video(report):
    from pathlib import Path

    for key in ("rough", "scan"):
        assert Path(report[key]["snapshot"]).stat().st_size > 10_000
    assert report["video"] and Path(report["video"]).stat().st_size > 10_000
