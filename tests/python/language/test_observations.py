"""Per-track colour samples and points gathered from frame and perception events."""

from types import SimpleNamespace as NS

import numpy as np

from grasp_pipeline.language import LanguageConfig, ObservationRecorder
from grasp_pipeline.language.observations import TrackObservation, add_points
from grasp_pipeline.orchestration.events import EventBus, FrameEvent, PerceptionEvent


def _frame_and_result(labels, rgb, points, estimate_labels, tids):
    frame = NS(points_world=points, rgb=rgb)
    raw = NS(estimate_labels=estimate_labels, tids=tids)
    result = NS(raw=raw, points=points, labels=np.asarray(labels))
    return frame, result


def test_a_groups_rows_give_its_tracks_points_and_colours():
    h, w = 2, 3
    points = np.arange(h * w * 3, dtype=np.float32).reshape(-1, 3) * 0.01
    rgb = np.zeros((h, w, 3), np.uint8)
    rgb[0, :] = (200, 0, 0)
    rgb[1, :] = (0, 0, 200)
    labels = [0, 0, 0, 1, 1, -1]             # group 0 = top row, group 1 = first two of row 2
    frame, result = _frame_and_result(labels, rgb, points, [1, 0], [7, 3])
    bus = EventBus()
    rec = ObservationRecorder(LanguageConfig(shape_voxel_m=1e-4)).attach(bus)
    bus.publish(FrameEvent(0.0, frame))
    bus.publish(PerceptionEvent(0.0, result, ()))
    assert sorted(rec.tracks) == [3, 7]
    assert (rec.tracks[3].colour_samples() == [200, 0, 0]).all() and len(rec.tracks[3].points) == 3
    assert (rec.tracks[7].colour_samples() == [0, 0, 200]).all()
    np.testing.assert_allclose(np.sort(rec.tracks[7].points[:, 0]), points[3:5, 0])
    assert bus.failures == []


def test_a_result_of_another_frame_is_ignored():
    pts = np.zeros((1, 3), np.float32)
    frame, _ = _frame_and_result([0], np.zeros((1, 1, 3), np.uint8), pts, [0], [1])
    _, other = _frame_and_result([0], None, pts.copy(), [0], [1])
    rec = ObservationRecorder()
    rec.on_frame(FrameEvent(0.0, frame))
    rec.on_perception(PerceptionEvent(0.0, other, ()))
    assert rec.tracks == {}


def test_colour_samples_per_frame_are_capped_and_points_thinned():
    n = 1000
    points = np.random.default_rng(0).uniform(0, 0.01, (n, 3))
    frame, result = _frame_and_result(np.zeros(n, int), np.full((n, 1, 3), 90, np.uint8), points, [0], [5])
    rec = ObservationRecorder(LanguageConfig(colour_samples_per_frame=50, shape_voxel_m=0.005))
    for _ in range(3):
        rec.on_frame(FrameEvent(0.0, frame))
        rec.on_perception(PerceptionEvent(0.0, result, ()))
    obs = rec.tracks[5]
    assert obs.frames == 3 and len(obs.colour_samples()) == 150
    assert len(obs.points) <= 8            # a 1 cm cube in 5 mm voxels
    rec.forget()
    assert rec.tracks == {}


def test_points_are_kept_once_per_voxel_and_capped():
    rng = np.random.default_rng(1)
    obs = TrackObservation()
    a = np.array([[0.0011, 0.0, 0.0], [0.0031, 0.0, 0.0]])
    add_points(obs, a, 0.002, 100, rng)
    add_points(obs, np.array([[0.0019, 0.0001, 0.0], [0.0051, 0.0, 0.0]]), 0.002, 100, rng)
    np.testing.assert_allclose(np.sort(obs.points[:, 0]), [0.0011, 0.0031, 0.0051])  # first per voxel
    assert np.all(np.diff(obs.keys) > 0) and len(obs.keys) == len(obs.points)
    add_points(obs, rng.uniform(0, 1, (500, 3)), 0.002, 100, rng)
    assert len(obs.points) == 100 and len(obs.keys) == 100
