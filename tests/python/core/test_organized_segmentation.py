"""Segmentation of neighbouring and touching objects in organized RGB-D frames
(``scene_filter.segment_*``, cpp organized_segmentation), and the range-dependent minimum
object height. Synthetic frames from :mod:`grasp_pipeline.perception.synthetic` (ray-cast,
depth noise along the ray)."""

import numpy as np
import pytest

from grasp_pipeline import _core
from grasp_pipeline.perception import PerceptionSession, SceneFilterConfig
from grasp_pipeline.perception import synthetic as syn
from grasp_pipeline.robot.depth_noise import DepthNoiseConfig

W = syn.PinholeCamera().width_px


def _frame(objects, eye=(0.52, 0.0, 0.62), target=(0.52, 0.0, 0.2), seed=0, noise=0.002):
    scene = syn.Tabletop(objects=tuple(objects))
    T = syn.look_at(np.array(eye), np.array(target))
    pts, _ = syn.render_depth(scene, T, noise_sigma_m=noise, rng=np.random.default_rng(seed))
    return pts, T


def _objects(pts, T, organized=True, rgb=None, **cfg):
    s = PerceptionSession(SceneFilterConfig(**cfg))
    fr = s.process(pts, T[:3, 3], 0.0, image_width_px=W if organized else 0, rgb=rgb)
    return fr


def _label_at(fr, pts, xy):
    """The label of the valid point nearest (horizontally) to xy among object points."""
    obj = fr.labels >= 0
    d = np.linalg.norm(pts[obj, :2] - np.asarray(xy), axis=1)
    return int(fr.labels[obj][np.argmin(d)])


def test_two_cubes_3mm_apart_are_two_objects():
    # 5 cm cubes whose faces are 3 mm apart: Euclidean clustering (eps 15 mm) merges them.
    a = syn.Box(center_xy=(0.52, -0.0265), size_m=(0.05, 0.05, 0.05))
    b = syn.Box(center_xy=(0.52, 0.0265), size_m=(0.05, 0.05, 0.05))
    pts, T = _frame([a, b], eye=(0.40, 0.0, 0.60))
    euclid = _objects(pts, T, organized=False)
    assert len(euclid.raw.filter.cluster_ids) == 1  # the old behaviour this fixes
    fr = _objects(pts, T)
    assert fr.raw.filter.organized
    assert len(fr.raw.filter.cluster_ids) == 2
    assert _label_at(fr, pts, (0.52, -0.03)) != _label_at(fr, pts, (0.52, 0.03))
    assert len(fr.estimates) == 2
    widths = sorted(round(min(e.extents[0], e.extents[1]), 2) for e in fr.estimates)
    assert widths == [0.05, 0.05]


def test_two_touching_boxes_of_different_heights_are_two_objects():
    a = syn.Box(center_xy=(0.52, -0.025), size_m=(0.06, 0.05, 0.04))
    b = syn.Box(center_xy=(0.52, 0.025), size_m=(0.06, 0.05, 0.07))  # touching a (shared face)
    # Seen from the tall box's side: its top edge hides the step, a range discontinuity. (From
    # the other side the step's face joins the two tops: a concave junction, not handled.)
    pts, T = _frame([a, b], eye=(0.52, 0.25, 0.62))
    fr = _objects(pts, T)
    assert len(fr.raw.filter.cluster_ids) == 2
    heights = sorted(round(e.height_m, 2) for e in fr.estimates)
    assert heights == [0.04, 0.07]


def _two_colour_rgb(pts, split_y, colours):
    """An (H, W, 3) image: colour 0 where y < split_y, colour 1 elsewhere, shaded randomly
    (a brightness factor per pixel, as Lambert shading and noise would)."""
    rng = np.random.default_rng(3)
    shade = rng.uniform(0.6, 1.0, len(pts))[:, None]
    c = np.where((pts[:, 1] < split_y)[:, None], np.array(colours[0]), np.array(colours[1]))
    img = np.nan_to_num(c * shade, nan=0.0).astype(np.uint8)
    return img.reshape(-1, W, 3)


def test_touching_boxes_of_one_height_are_told_apart_by_colour():
    a = syn.Box(center_xy=(0.52, -0.025), size_m=(0.06, 0.05, 0.05))
    b = syn.Box(center_xy=(0.52, 0.025), size_m=(0.06, 0.05, 0.05))
    pts, T = _frame([a, b])
    assert len(_objects(pts, T).raw.filter.cluster_ids) == 1  # depth alone cannot
    rgb = _two_colour_rgb(pts, 0.0, [(200, 40, 40), (40, 60, 200)])
    fr = _objects(pts, T, rgb=rgb)
    assert len(fr.raw.filter.cluster_ids) == 2
    # One colour in two shades is one object (hue, not brightness, is compared).
    same = _two_colour_rgb(pts, 0.0, [(200, 40, 40), (120, 24, 24)])
    assert len(_objects(pts, T, rgb=same).raw.filter.cluster_ids) == 1


def test_rgb_is_validated():
    pts, T = _frame([syn.Box(center_xy=(0.52, 0.0), size_m=(0.05, 0.05, 0.05))])
    s = PerceptionSession()
    with pytest.raises(TypeError, match="uint8"):
        s.process(pts, T[:3, 3], 0.0, image_width_px=W, rgb=np.zeros((480, W, 3), np.float32))
    with pytest.raises(ValueError, match="rgb: expected shape"):
        s.process(pts, T[:3, 3], 0.0, image_width_px=W, rgb=np.zeros((10, W, 3), np.uint8))
    with pytest.raises(ValueError, match="image_width"):
        s.process(pts, T[:3, 3], 0.0, image_width_px=7)


def test_unorganized_cloud_keeps_euclidean_clustering_and_every_row_its_label():
    pts, T = syn.tabletop_frame(seed=0)
    valid = pts[np.isfinite(pts[:, 0])]
    fr = _objects(valid, T, organized=False)
    assert not fr.raw.filter.organized and len(fr.labels) == len(valid)
    assert len(fr.estimates) == 3
    org = _objects(pts, T)
    assert org.raw.filter.organized and len(org.labels) == len(pts)
    assert len(org.estimates) == 3
    # Same objects both ways on the reference scene (objects >= 12 cm apart).
    c1 = sorted(tuple(np.round(e.center[:2], 2)) for e in fr.estimates)
    c2 = sorted(tuple(np.round(e.center[:2], 2)) for e in org.estimates)
    assert c1 == c2


def test_organized_segmentation_can_be_switched_off():
    a = syn.Box(center_xy=(0.52, -0.0265), size_m=(0.05, 0.05, 0.05))
    b = syn.Box(center_xy=(0.52, 0.0265), size_m=(0.05, 0.05, 0.05))
    pts, T = _frame([a, b], eye=(0.40, 0.0, 0.60))
    fr = _objects(pts, T, segment_organized=False)
    assert not fr.raw.filter.organized and len(fr.raw.filter.cluster_ids) == 1


def test_core_height_rule_refuses_low_clusters_far_from_the_camera():
    # A 12 mm high patch seen from 0.5 m is an object; from 2 m (sigma = 50 mm) it is noise.
    rng = np.random.default_rng(0)
    table = np.c_[rng.uniform(-1, 1, (20000, 2)), np.zeros(20000)]
    patch = np.c_[rng.uniform(0, 0.05, (400, 2)), rng.uniform(0.011, 0.013, 400)]
    pts = np.vstack([table, patch]).astype(np.float32)
    for cam_dist, objects in ((0.5, 1), (2.0, 0)):
        noise = DepthNoiseConfig()
        per = _core.Perception(SceneFilterConfig().to_core(noise), PerceptionSession().obb_config.to_core(noise))
        fr = per.process(pts, np.array([0.0, 0.0, cam_dist]), 0.0)
        assert len(fr.filter.cluster_ids) == objects
        assert fr.filter.num_too_low == 1 - objects
    info = [c for c in fr.filter.clusters if c.too_low][0]
    assert info.range_m == pytest.approx(2.0, abs=0.02)
    assert info.min_height_m == pytest.approx(0.05, rel=0.02)
    assert 0.011 <= info.height_m <= 0.013


def test_real_capture_like_cloud_reports_the_near_objects_and_no_far_noise():
    from real_capture_like import CAMERA, FAR_PATCH_CENTRES, NEAR_BOXES, floor_capture

    pts = floor_capture()
    fr = PerceptionSession().process(pts, CAMERA, 0.0)
    assert len(fr.estimates) == len(NEAR_BOXES)
    for (c, _) in NEAR_BOXES:
        assert min(np.linalg.norm(e.center[:2] - c) for e in fr.estimates) < 0.01
    assert fr.raw.filter.num_too_low >= len(FAR_PATCH_CENTRES) - 1
    # Without the rule the far noise is reported as objects (as measured before the rule existed).
    off = PerceptionSession(SceneFilterConfig(object_min_height_sigmas=0.0)).process(pts, CAMERA, 0.0)
    far = [e for e in off.estimates if np.linalg.norm(e.center[:2]) > 1.5]
    assert len(far) >= 3


def _bottle(x, y, base_z=0.2):
    """A bottle seen from above: a 64 mm body 100 mm high, a shoulder of 2 mm stairs rising
    2 mm each (45 deg) to 32 mm, and a 24 mm cap 15 mm above the shoulder's top."""
    parts = [syn.Cylinder((x, y), 0.064, 0.100, base_z)]
    top = base_z + 0.100
    for d_mm in range(60, 30, -4):
        parts.append(syn.Cylinder((x, y), d_mm / 1000.0, 0.002, top))
        top += 0.002
    parts.append(syn.Cylinder((x, y), 0.024, 0.015, top))
    return parts


def test_a_bottle_seen_from_above_is_one_object_though_its_cap_is_a_step_up():
    pts, T = _frame(_bottle(0.52, 0.0), eye=(0.52, 0.0, 0.62))
    assert len(_objects(pts, T, segment_nest_fraction=0.0).raw.filter.cluster_ids) == 2  # cap apart
    fr = _objects(pts, T)
    assert len(fr.raw.filter.cluster_ids) == 1
    assert round(fr.estimates[0].height_m, 2) == 0.13


def test_a_box_on_a_larger_box_seen_from_above_stays_two_objects():
    lower = syn.Box(center_xy=(0.52, 0.0), size_m=(0.06, 0.06, 0.04))
    upper = syn.Box(center_xy=(0.52, 0.0), size_m=(0.03, 0.03, 0.03), base_z_m=0.24)
    pts, T = _frame([lower, upper], eye=(0.52, 0.0, 0.62))
    fr = _objects(pts, T)
    assert len(fr.raw.filter.cluster_ids) == 2
