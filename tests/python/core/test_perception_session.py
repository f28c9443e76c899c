"""The per-frame entry point (`_core.Perception`) and its Python face
(`grasp_pipeline.perception.PerceptionSession`) on the synthetic reference tabletop
(method.md §8's arrangement rendered by `grasp_pipeline.perception.synthetic`).
"""

import logging

import numpy as np
import pytest

from grasp_pipeline import _core
from grasp_pipeline.perception import PerceptionSession, SceneFilterConfig
from grasp_pipeline.perception import synthetic as syn

OBL = _core.ViewQuality.OBLIQUE
NAD = _core.ViewQuality.NADIR


def truth_centres():
    """(x, y, z) box centres of the reference objects, in tabletop order."""
    scene = syn.reference_tabletop()
    out = []
    for obj in scene.objects:
        h = obj.size_m[2] if isinstance(obj, syn.Box) else obj.height_m
        out.append(np.array([obj.center_xy[0], obj.center_xy[1], obj.base_z_m + h / 2]))
    return out


@pytest.fixture(scope="module")
def start_frame():
    pts, T = syn.tabletop_frame(seed=0)
    return pts, T


@pytest.fixture(scope="module")
def nadir_frame():
    """A frame from directly above the blue cube at the probing working distance."""
    T = syn.look_at(np.array([0.56, -0.03, 0.59]), np.array([0.56, -0.03, 0.2]))
    pts, _ = syn.render_depth(syn.reference_tabletop(), T, rng=np.random.default_rng(1))
    return pts, T


def match(estimates, centres):
    """Index of the estimate nearest to each true centre (horizontal)."""
    idx = []
    for c in centres:
        d = [np.linalg.norm(e.center[:2] - c[:2]) for e in estimates]
        idx.append(int(np.argmin(d)))
    assert len(set(idx)) == len(centres)
    return idx


def test_reference_frame_table_objects_and_oblique_views(start_frame):
    pts, T = start_frame
    per = _core.Perception(_core.SceneFilterParams(), _core.ObbParams())
    fr = per.process(pts, T[:3, 3], 0.0)
    f = fr.filter
    assert f.table is not None and f.table.height_m == pytest.approx(0.200, abs=0.0005)
    assert f.decision == _core.PlaneDecision.LOCKED and f.environment_emitted
    assert len(f.labels) == len(pts)
    assert len(fr.estimates) == 3 and fr.failures == [] and fr.tids == [0, 1, 2]
    assert sorted(fr.estimate_labels) == sorted(f.cluster_ids)
    centres = truth_centres()
    for k, i in enumerate(match(fr.estimates, centres)):
        e = fr.estimates[i]
        assert np.linalg.norm(e.center - centres[k]) < 0.005
        assert e.width_m == pytest.approx(0.05, abs=0.003)
        assert e.grasp_ok and e.resting
        assert fr.views[i].quality == OBL  # all oblique from the start pose
        assert fr.views[i].angle_deg > 5.0
    assert np.allclose(fr.camera_position, T[:3, 3]) and fr.time_s == 0.0
    # the tracker saw them: one OBLIQUE track each
    assert [t.tid for t in per.tracker.tracks] == [0, 1, 2]
    assert all(t.quality == OBL for t in per.tracker.tracks)


def test_view_from_directly_above_is_nadir_with_a_flat_pca(start_frame, nadir_frame):
    per = _core.Perception(_core.SceneFilterParams(), _core.ObbParams())
    pts0, T0 = start_frame
    per.process(pts0, T0[:3, 3], 0.0)
    pts, T = nadir_frame
    fr = per.process(pts, T[:3, 3], 1.0)
    blue = np.array([0.56, -0.03])
    i = int(np.argmin([np.linalg.norm(e.center[:2] - blue) for e in fr.estimates]))
    e, v = fr.estimates[i], fr.views[i]
    assert v.quality == NAD and v.angle_deg < 1.0
    assert e.pca_tilt_deg < 1.0
    assert e.width_m == pytest.approx(0.05, abs=0.003) and e.grasp_ok
    # the same track (matched by geometry), now NADIR with a restarted window
    track = next(t for t in per.tracker.tracks if t.tid == fr.tids[i])
    assert track.quality == NAD and track.window_size == 1
    assert np.array_equal(track.smoothed.center, e.center)
    others = [q for j, q in enumerate(fr.views) if j != i]
    assert all(q.quality == OBL for q in others)


def test_camera_position_comes_from_the_frame(start_frame):
    # the same cloud "captured" from right above the blue cube's centre would be NADIR for it
    pts, _ = start_frame
    per = _core.Perception(_core.SceneFilterParams(), _core.ObbParams())
    fr = per.process(pts, [0.56, -0.03, 0.6], 0.0)
    blue = int(np.argmin([np.linalg.norm(e.center[:2] - [0.56, -0.03]) for e in fr.estimates]))
    assert fr.views[blue].quality == NAD


def test_perception_retires_tracks_on_frames_without_objects(start_frame):
    pts, T = start_frame
    per = _core.Perception(_core.SceneFilterParams(), _core.ObbParams())
    per.process(pts, T[:3, 3], 0.0)
    table_only = pts[pts[:, 2] < 0.205]
    fr = per.process(table_only, T[:3, 3], 1.0)
    assert fr.estimates == [] and len(per.tracker.tracks) == 3
    per.process(table_only, T[:3, 3], 2.5)  # oblique tracks older than 2 s
    assert per.tracker.tracks == []
    per.reset()
    assert not per.scene_filter.persistence.locked


# --------------------------------------------------------------------------------------
# PerceptionSession (python/grasp_pipeline/perception/session.py)


def test_session_masks_partition_the_valid_rows_and_plane_is_latched(start_frame, caplog):
    pts, T = start_frame
    pts = pts.copy()
    pts[::97] = np.nan  # a few invalid rows
    s = PerceptionSession()
    assert s.plane is None and not s.plane_locked and s.band_m == 0.01
    with caplog.at_level(logging.INFO, logger="grasp_pipeline.perception"):
        fr = s.process(pts, T[:3, 3], 0.0)
    assert any("table plane locked" in r.getMessage() for r in caplog.records)
    assert fr.raw.filter.environment_emitted  # the first frame already locks
    valid = np.isfinite(pts).all(axis=1)
    obj, env = fr.object_mask, fr.environment_mask
    assert not np.any(obj & env)
    assert np.array_equal(obj | env, valid)
    assert np.array_equal(fr.labels == _core.LABEL_INVALID, ~valid)
    op, ol = fr.object_points()
    assert len(op) == len(ol) == int(obj.sum()) and np.all(ol >= 0)
    assert len(fr.environment_points()) == int(env.sum())
    assert len(fr.estimates) == 3 and fr.table.height_m == pytest.approx(0.2, abs=0.0005)
    # latched: readable at any time, also after a frame without a table in view
    fr2 = s.process(wall_cloud(z=(0.0, 0.18)), T[:3, 3], 0.1)  # below the table: environment
    assert fr2.raw.filter.decision == _core.PlaneDecision.KEPT_NO_FIT
    assert fr2.environment_mask.all() and not fr2.object_mask.any()
    assert s.plane_locked and s.plane.height_m == pytest.approx(0.2, abs=0.0005)
    assert fr2.table.height_m == pytest.approx(0.2, abs=0.0005)
    assert len(s.tracks()) == 3 and s.frames == 2
    assert "oblique" in s.view_labels(fr)
    s.reset()
    assert s.plane is None and s.frames == 0


def wall_cloud(n=5000, z=(0.0, 1.0)):
    """Only a vertical wall: no horizontal plane to fit."""
    r = np.random.default_rng(0)
    return np.column_stack([np.full(n, 1.3) + r.normal(0, 0.002, n), r.uniform(-0.5, 0.5, n),
                            r.uniform(z[0], z[1], n)]).astype(np.float32)


def test_session_emits_no_environment_before_a_lock():
    wall = wall_cloud()
    s = PerceptionSession(SceneFilterConfig(plane_init_frames=3))
    fr = s.process(wall, [0.3, 0.0, 0.6], 0.0)
    assert s.plane is None and not fr.raw.filter.environment_emitted
    assert not fr.environment_mask.any() and len(fr.environment_points()) == 0
    assert not fr.object_mask.any()
    s.process(wall, [0.3, 0.0, 0.6], 0.1)
    fr = s.process(wall, [0.3, 0.0, 0.6], 0.2)  # fallback: the whole cloud is environment
    assert fr.raw.filter.fallback and fr.environment_mask.all()


def test_a_close_view_from_directly_above_is_not_nadir():
    """(ours) nadir_min_distance_m: the camera passing low over an object sees part of it."""
    from grasp_pipeline import _core
    from grasp_pipeline.perception.synthetic import look_at, reference_tabletop, render_depth

    scene = reference_tabletop()
    cube = scene.objects[0]
    top = np.array([cube.center_xy[0], cube.center_xy[1], 0.25])
    results = {}
    for height in (0.39, 0.15):  # probing height vs a low pass
        T = look_at(eye=top + np.array([0, 0, height]), target=top)
        pts, _ = render_depth(scene, T, rng=np.random.default_rng(1))
        per = _core.Perception(_core.SceneFilterParams(), _core.ObbParams())
        per.process(pts, T[:3, 3], 0.0)
        frame = per.process(pts, T[:3, 3], 0.1)
        k = int(np.argmin([np.linalg.norm(np.asarray(e.center[:2]) - top[:2]) for e in frame.estimates]))
        results[height] = frame.views[k]
    assert results[0.39].quality == _core.ViewQuality.NADIR
    assert results[0.15].quality == _core.ViewQuality.OBLIQUE
    assert results[0.15].angle_deg < 5.0  # by angle alone it would have been NADIR
