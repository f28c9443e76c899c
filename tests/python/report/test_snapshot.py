"""RViz-like PNG snapshots: objects red, environment blue, boxes green, arrows orange."""

from __future__ import annotations


import imageio.v3 as iio
import numpy as np
import pytest

from grasp_pipeline import _core
from grasp_pipeline.perception import PerceptionSession
from grasp_pipeline.perception.synthetic import tabletop_frame
from grasp_pipeline.report.snapshot import box_corners, render_snapshot, snapshot_image


@pytest.fixture(scope="module")
def frame():
    pts, T = tabletop_frame(seed=1)
    session = PerceptionSession()
    fr = session.process(pts, camera_position=T[:3, 3], time_s=0.0)
    assert session.plane is not None and len(fr.estimates) == 3
    boxes = [(e.center, e.R_box, e.extents) for e in fr.estimates]
    grasps = []
    for e in fr.estimates:
        g = _core.best_grasp_from_estimate(e, session.plane)
        grasps.append((g.position, np.asarray(g.R)[:, 0]))
    obj, labels = fr.object_points()
    return {"pts": pts, "obj": obj, "labels": labels, "env": fr.environment_points(),
            "boxes": boxes, "grasps": grasps, "plane": session.plane}


def colour_counts(img: np.ndarray) -> dict[str, int]:
    r, g, b = (img[..., k].astype(int) for k in range(3))
    return {
        "red": int(np.count_nonzero((r > 200) & (g < 70) & (b < 70))),
        "blue": int(np.count_nonzero((b > 200) & (r < 90) & (g < 130))),
        "green": int(np.count_nonzero((g > 170) & (r < 80) & (b < 80))),
        "orange": int(np.count_nonzero((r > 220) & (g > 100) & (g < 180) & (b < 60))),
    }


def test_snapshot_of_a_full_frame_has_the_rviz_colours(frame, tmp_path):
    assert len(frame["pts"]) == 307200
    path = tmp_path / "sub" / "snap.png"
    out = render_snapshot(path, frame["obj"], frame["labels"], frame["env"], frame["boxes"],
                          frame["grasps"], plane=frame["plane"], title="reference frame")
    assert out == str(path) and path.stat().st_size > 20_000
    img = iio.imread(path)
    assert img.ndim == 3 and img.shape[0] >= 600 and img.shape[1] >= 800
    counts = colour_counts(img[..., :3])
    assert counts["red"] > 500, counts
    assert counts["blue"] > 500, counts
    assert counts["green"] > 100, counts
    assert counts["orange"] > 20, counts


def test_only_environment_gives_no_red(tmp_path):
    env = np.random.default_rng(0).uniform([0, -0.5, 0.2], [1, 0.5, 0.2], size=(5000, 3))
    env[::10] = np.nan  # NaN rows are dropped, not drawn
    path = tmp_path / "env.png"
    render_snapshot(path, None, None, env, title="environment only")
    counts = colour_counts(iio.imread(path)[..., :3])
    assert counts["blue"] > 200 and counts["red"] == 0 and counts["green"] == 0


def test_snapshot_image_and_plane_tuple(frame):
    img = snapshot_image(frame["obj"][:2000], None, frame["env"][:5000], frame["boxes"][:1],
                         [], plane=((0.0, 0.0, 1.0), -0.2), size_px=(400, 300))
    assert img.shape == (300, 400, 3) and img.dtype == np.uint8
    counts = colour_counts(img)
    assert counts["red"] > 20 and counts["green"] > 10


def test_box_corners():
    R = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # 90 deg yaw
    k = box_corners([1.0, 2.0, 3.0], R, [0.2, 0.1, 0.4])
    assert k.shape == (8, 3)
    np.testing.assert_allclose(k.min(axis=0), [0.95, 1.9, 2.8])
    np.testing.assert_allclose(k.max(axis=0), [1.05, 2.1, 3.2])
