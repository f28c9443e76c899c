"""method.md §3 (grasp pose, camera-above pose, view quality) through the bindings."""

import math

import numpy as np
import pytest

import synthetic_clouds as sc
from grasp_pipeline import _core

TABLE = _core.Plane([0, 0, 1], -0.2)


def estimate(yaw_deg=25.0, plane=TABLE, pts=None):
    if pts is None:
        pts = sc.box_surface((0.5, -0.05), (0.03, 0.06, 0.05), yaw_rad=math.radians(yaw_deg), sides=(0, 1),
                             seed=1)
    res = _core.estimate_object(pts, plane, _core.ObbParams(), band=0.01)
    assert res.estimate is not None, res.failure
    return res.estimate


def is_rotation(R):
    return np.allclose(R.T @ R, np.eye(3), atol=1e-9) and abs(np.linalg.det(R) - 1) < 1e-9


def rz(a):
    return np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1.0]])


def test_top_down_rotation_columns():
    e = estimate()
    n = np.array([0, 0, 1.0])
    R = _core.top_down_rotation(e.R_box, n)
    closing = e.R_box[:, 0]
    assert is_rotation(R)
    assert np.allclose(R[:, 0], n)
    y = np.cross(closing, n)
    assert np.allclose(R[:, 1], y / np.linalg.norm(y))
    assert np.allclose(R[:, 2], closing)


def test_top_down_rotation_fails_when_closing_is_parallel_to_n():
    R_box = np.array([[0, 1.0, 0], [0, 0, 1], [1, 0, 0]])  # column 0 = +z
    assert np.allclose(R_box[:, 0], [0, 0, 1])
    assert _core.top_down_rotation(R_box, [0, 0, 1]) is None
    assert _core.top_down_rotation(R_box, [0, 0, -2]) is None


def test_best_grasp_convention():
    e = estimate()
    g = _core.best_grasp_from_estimate(e, TABLE)
    assert g is not None
    assert is_rotation(g.R)
    assert np.allclose(g.R[:, 0], [0, 0, -1])  # approach axis points INTO the object (down)
    assert abs(abs(g.R[:, 2] @ e.R_box[:, 0]) - 1) < 1e-12  # closing axis, sign irrelevant
    assert np.allclose(g.position, e.center)  # contact point = estimate centre
    assert g.width_m == e.width_m and g.width_m == pytest.approx(0.03, abs=0.0015)
    assert g.score == 0.0  # no fake confidence
    # the published R is the top-down R with columns 0 and 2 negated
    R = _core.top_down_rotation(e.R_box, TABLE.n)
    assert np.allclose(g.R, R @ np.diag([-1.0, 1.0, -1.0]))


def test_best_grasp_on_a_tilted_table_approaches_along_minus_n():
    n = np.array([0.08, -0.05, 1.0])
    n /= np.linalg.norm(n)
    plane = _core.Plane(n, -0.2 * n[2])
    R = _core.top_down_rotation(np.eye(3), n)
    assert is_rotation(R) and np.allclose(R[:, 0], n)
    pts = sc.box_top((0.5, 0.0), (0.03, 0.06), 0.25, seed=2)
    e = _core.estimate_object(pts, plane, _core.ObbParams(), band=0.01).estimate
    g = _core.best_grasp_from_estimate(e, plane)
    assert is_rotation(g.R) and np.allclose(g.R[:, 0], -n)


def test_camera_above_pose():
    ready = _core.Pose(rz(0.7) @ np.diag([1.0, -1.0, -1.0]), [0.3, 0.1, 0.65])
    obj = np.array([0.56, -0.03, 0.225])
    cam = _core.camera_above_pose(obj, TABLE, ready)
    assert is_rotation(cam.R)
    assert np.allclose(cam.R[:, 2], [0, 0, -1])  # optical axis = -n
    x_ready = ready.R[:, 0]
    x_proj = x_ready - x_ready[2] * np.array([0, 0, 1.0])
    assert np.allclose(cam.R[:, 0], x_proj / np.linalg.norm(x_proj))
    assert np.allclose(cam.R[:, 1], np.cross(cam.R[:, 2], cam.R[:, 0]))
    assert np.allclose(cam.t, [0.56, -0.03, 0.65])  # object x, y at the ready camera height


def test_camera_above_pose_falls_back_to_u_when_the_ready_x_is_vertical():
    R_ready = np.array([[0, 1.0, 0], [0, 0, 1.0], [1.0, 0, 0]])  # x column = +z
    assert abs(np.linalg.det(R_ready) - 1) < 1e-12
    ready = _core.Pose(R_ready, [0.3, 0.0, 0.6])
    cam = _core.camera_above_pose([0.5, 0.0, 0.2], TABLE, ready)
    u, _ = _core.in_plane_basis([0, 0, 1])
    assert np.allclose(cam.R[:, 0], u) and is_rotation(cam.R)


def test_camera_above_flange_target_composes_with_the_camera_mount():
    ready = _core.Pose(np.diag([1.0, -1.0, -1.0]), [0.3, 0.0, 0.6])
    R_lc = rz(-math.pi / 4) @ np.array([[1.0, 0, 0], [0, math.cos(0.1), -math.sin(0.1)],
                                         [0, math.sin(0.1), math.cos(0.1)]])
    mount = _core.Pose(R_lc, [0.05, -0.02, 0.04])  # camera pose in the flange frame
    obj = [0.5, 0.1, 0.225]
    flange = _core.camera_above_flange_target(obj, TABLE, ready, mount)
    cam = _core.camera_above_pose(obj, TABLE, ready)
    assert np.allclose(flange.R, cam.R @ R_lc.T)
    assert np.allclose(flange.t, cam.t - flange.R @ mount.t)
    # flange pose o camera-in-flange = the camera pose
    T = flange.matrix() @ mount.matrix()
    assert np.allclose(T, cam.matrix())


def test_view_quality_nadir_and_oblique():
    n = [0, 0, 1]
    obj = np.array([0.5, 0.0, 0.225])
    v = _core.assess_view(obj, obj + [0, 0, 0.39], n, 5.0)
    assert v.quality == _core.ViewQuality.NADIR and v.angle_deg == pytest.approx(0.0, abs=1e-9)
    for deg, q in [(4.9, _core.ViewQuality.NADIR), (5.1, _core.ViewQuality.OBLIQUE),
                   (40.0, _core.ViewQuality.OBLIQUE)]:
        off = 0.39 * math.tan(math.radians(deg))
        v = _core.assess_view(obj, obj + [off, 0, 0.39], n, 5.0)
        assert v.quality == q and v.angle_deg == pytest.approx(deg, abs=1e-9)
    v = _core.assess_view(obj, obj, n, 5.0)  # coincident
    assert v.quality == _core.ViewQuality.OBLIQUE and math.isnan(v.angle_deg)
    # camera BELOW the object looking up is not a nadir view
    v = _core.assess_view(obj, obj - [0, 0, 0.3], n, 5.0)
    assert v.quality == _core.ViewQuality.OBLIQUE and v.angle_deg == pytest.approx(180.0)
    assert int(_core.ViewQuality.NADIR) > int(_core.ViewQuality.OBLIQUE)


def test_best_grasp_value_type():
    g = _core.BestGrasp(np.eye(3), [0.1, 0.2, 0.3], 0.05)
    assert g.score == 0.0 and g.width_m == 0.05 and np.allclose(g.position, [0.1, 0.2, 0.3])
    with pytest.raises(ValueError):
        _core.BestGrasp(np.diag([1.0, 1.0, -1.0]), [0, 0, 0], 0.05)
