"""The scene cloud: per-point owners from a frame's labels (cluster → estimate → track)."""

import types

import numpy as np

from grasp_pipeline.orchestration.scene.scene_cloud import (ENVIRONMENT, UNTRACKED, cloud_from_frame,
                                                         voxel_thin)


def _frame(points, labels, estimate_labels, tids, emitted=True):
    labels = np.asarray(labels)
    raw = types.SimpleNamespace(estimate_labels=estimate_labels, tids=tids)
    env = (labels == -1) if emitted else np.zeros(len(labels), dtype=bool)
    return types.SimpleNamespace(points=np.asarray(points, float), labels=labels, raw=raw,
                                 environment_mask=env)


PLANE = types.SimpleNamespace(n=[0.0, 0.0, 1.0], c=-0.2)


def test_points_take_the_track_of_their_cluster_and_invalid_rows_are_dropped():
    pts = [[0.5, 0, 0.25], [0.6, 0, 0.24], [0.7, 0, 0.2], [np.nan, 0, 0], [0.8, 0, 0.23]]
    fr = _frame(pts, [0, 1, -1, -2, 2], estimate_labels=[1, 0], tids=[7, 3])
    cloud = cloud_from_frame(fr, PLANE, 0.01, 0.001)
    owners = {tuple(np.round(p, 3)): int(o) for p, o in zip(cloud.points, cloud.owner)}
    assert owners == {(0.5, 0.0, 0.25): 3, (0.6, 0.0, 0.24): 7, (0.7, 0.0, 0.2): ENVIRONMENT,
                      (0.8, 0.0, 0.23): UNTRACKED}
    assert np.allclose(cloud.heights_m(np.array([[0.5, 0, 0.25]])), 0.05)
    assert len(cloud.near((0.5, 0.0), 0.05)) == 1 and len(cloud.of(7)) == 1


def test_environment_is_left_out_until_the_filter_emits_it():
    fr = _frame([[0.5, 0, 0.25], [0.7, 0, 0.2]], [0, -1], [0], [4], emitted=False)
    cloud = cloud_from_frame(fr, PLANE, 0.01, 0.001)
    assert cloud.owner.tolist() == [4]


def test_voxel_thinning_keeps_one_point_per_voxel_and_owner():
    pts = np.array([[0.0, 0, 0], [0.001, 0, 0], [0.001, 0, 0], [0.01, 0, 0]])
    own = np.array([1, 1, 2, 1])
    p, o = voxel_thin(pts, own, 0.003)
    assert len(p) == 3 and sorted(o.tolist()) == [1, 1, 2]
