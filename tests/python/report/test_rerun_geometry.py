"""What a recording draws, as arrays: boxes, grasps, depth, clouds, TCP positions."""

from types import SimpleNamespace

import numpy as np
from scipy.spatial.transform import Rotation

from grasp_pipeline import _core
from grasp_pipeline.report import rerun_geometry as geo
from grasp_pipeline.robot import description as rm


def test_boxes_keep_pose_size_label_and_quality_colour():
    R = Rotation.from_euler("z", 30, degrees=True).as_matrix()
    est = SimpleNamespace(center=[0.5, 0.1, 0.2], extents=[0.05, 0.04, 0.06], R_box=R)
    tracks = [SimpleNamespace(tid=4, quality=_core.ViewQuality.NADIR, smoothed=est),
              SimpleNamespace(tid=7, quality=_core.ViewQuality.OBLIQUE, smoothed=est)]
    b = geo.track_boxes(tracks)
    assert len(b) == 2 and b.labels[0] == "#4 nadir 50x40x60 mm" and b.labels[1].startswith("#7 oblique")
    np.testing.assert_allclose(Rotation.from_quat(b.quaternions_xyzw[0]).as_matrix(), R, atol=1e-12)
    np.testing.assert_allclose(b.half_sizes[0], [0.025, 0.02, 0.03])
    assert tuple(b.colors[0]) == geo.NADIR_RGB and tuple(b.colors[1]) == geo.OBLIQUE_RGB


def test_a_reflected_box_basis_still_gives_a_rotation():
    est = SimpleNamespace(center=[0, 0, 0], extents=[1, 1, 1], R_box=np.diag([1.0, 1.0, -1.0]))
    b = geo.track_boxes([SimpleNamespace(tid=0, quality=_core.ViewQuality.NADIR, smoothed=est)])
    np.testing.assert_allclose(np.abs(b.quaternions_xyzw[0]), [0, 0, 0, 1], atol=1e-12)


def test_no_tracks_give_empty_batches():
    b = geo.track_boxes([])
    assert len(b) == 0 and b.centers.shape == (0, 3) and b.quaternions_xyzw.shape == (0, 4)


def test_a_grasp_is_drawn_as_fingers_its_width_apart_ending_at_the_contact_point():
    R = np.column_stack([[0, 0, -1.0], [-1.0, 0, 0], [0, 1.0, 0]])  # approach -z, closing y
    g = _core.BestGrasp(R, np.array([0.5, 0.0, 0.2]), 0.06)
    (strip,) = geo.gripper_strips(g, finger_m=0.05)
    np.testing.assert_allclose(strip[0], [0.5, 0.03, 0.2])
    np.testing.assert_allclose(strip[1], [0.5, 0.03, 0.25])       # finger base above (against approach)
    np.testing.assert_allclose(strip[3], [0.5, -0.03, 0.2])
    origins, vectors = geo.approach_arrows([g], length_m=0.08)
    np.testing.assert_allclose(origins[0] + vectors[0], [0.5, 0.0, 0.2])
    np.testing.assert_allclose(vectors[0], [0, 0, -0.08])


def test_depth_becomes_millimetres_with_zero_for_no_return():
    d = np.array([[0.4, np.nan], [0.0, 70.0]], dtype=np.float32)
    np.testing.assert_array_equal(geo.depth_mm(d), [[400, 0], [0, 65535]])


def test_clouds_are_split_by_label_and_thinned_with_a_fixed_stride():
    pts = np.arange(300, dtype=np.float32).reshape(100, 3)
    pts[5] = np.nan
    labels = np.where(np.arange(100) < 10, 1, -1)
    result = SimpleNamespace(object_points=lambda: (pts[labels >= 0], labels[labels >= 0]),
                             environment_points=lambda: pts[labels == -1])
    obj, env = geo.split_cloud(result, 100, 30)
    assert len(obj) == 9 and np.isfinite(obj).all()               # the NaN row dropped
    assert len(env) == 30 and env[0, 0] == 30 and env[-1, 0] == 297
    assert len(geo.split_cloud(result, 0, 0)[0]) == 0


def test_sample_rows_keeps_both_ends():
    rows = geo.sample_rows(1000, 60)
    assert rows[0] == 0 and rows[-1] == 999 and len(rows) <= 60
    np.testing.assert_array_equal(geo.sample_rows(5, 60), np.arange(5))


def test_tcp_positions_equal_mujoco_forward_kinematics():
    model = rm.load_robot_model()
    Q = np.array([rm.READY_Q, rm.NEUTRAL_Q])
    expected = [(rm.forward_kinematics(q, model) @ rm.flange_T_tcp(model))[:3, 3] for q in Q]
    np.testing.assert_allclose(geo.TcpKinematics().positions(Q), expected, atol=1e-9)
