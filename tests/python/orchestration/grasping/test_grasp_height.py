"""The contact height of top-down grasps (ours): the pads stay above the table for low objects,
the palm above the object for tall ones; in between method.md §3's box centre."""

from types import SimpleNamespace

import numpy as np
import pytest

from grasp_pipeline import _core
from grasp_pipeline.orchestration.config import GraspConfig, GraspFitConfig
from grasp_pipeline.orchestration.grasping.fit import contact_height_m
from grasp_pipeline.orchestration.grasping.opening import max_grasp_width_m
from grasp_pipeline.orchestration.grasping.source import GraspRequest
from grasp_pipeline.orchestration.grasping.top_down import GeometricGraspSource
from grasp_pipeline.robot.description import HAND_BODY, TCP_SITE, HandClearances, hand_clearances

CFG = GraspConfig()
HAND = HandClearances(pad_below_tcp_m=0.011, palm_above_tcp_m=0.0394, finger_thickness_m=0.02,
                      finger_width_m=0.019)


def test_hand_clearances_come_from_the_model():
    import mujoco

    from grasp_pipeline.robot.description import _robot_model_cached

    m = _robot_model_cached()
    h = hand_clearances(m)
    pad = m.geom("leftfinger_pad")
    finger = m.body(int(pad.bodyid[0]))
    tcp_z = float(m.site(TCP_SITE).pos[2])
    assert h.pad_below_tcp_m == pytest.approx(float(finger.pos[2] + pad.pos[2] + pad.size[2]) - tcp_z)
    palm = m.geom("hand_col1")
    assert int(palm.bodyid[0]) == m.body(HAND_BODY).id
    assert h.palm_above_tcp_m == pytest.approx(tcp_z - float(palm.pos[2] + palm.size[2]))
    assert 0.0 < h.pad_below_tcp_m < h.palm_above_tcp_m < 0.1
    assert int(mujoco.mjtGeom.mjGEOM_BOX) == int(palm.type[0])


@pytest.mark.parametrize("height_m, expected_m", [
    (0.05, 0.025),                     # a 5 cm cube: the box centre (method.md §3)
    (0.02, 0.011 + 0.004),             # a 2 cm soap bar: pads 4 mm above the table
    (0.20, 0.20 + 0.01 - 0.0394),      # a 20 cm bottle: palm 10 mm above its top
])
def test_contact_height(height_m, expected_m):
    assert contact_height_m(height_m, HAND, CFG) == pytest.approx(expected_m)


def test_geometric_source_raises_both_grasps_of_a_tall_object():
    n = np.array([0.0, 0.0, 1.0])
    plane = SimpleNamespace(n=n, c=-0.2)
    est = SimpleNamespace(center=[0.5, 0.0, 0.3], height_m=0.2, perp_width_m=0.06, width_m=0.05,
                          R_box=np.eye(3))
    R = np.column_stack([-n, np.cross(np.array([1.0, 0, 0]), -n), np.array([1.0, 0, 0])])
    published = _core.BestGrasp(R, np.array([0.5, 0.0, 0.3]), 0.05)
    scene = SimpleNamespace(plane=plane)
    req = GraspRequest((0.5, 0.0), SimpleNamespace(smoothed=est), published, scene, max_grasp_width_m(GraspFitConfig()))
    grasps = GeometricGraspSource(CFG, HAND).propose(req)
    assert len(grasps) == 2
    for g in grasps:
        assert float(g.position[2]) == pytest.approx(0.2 + 0.2 + 0.01 - 0.0394)
        assert np.allclose(np.asarray(g.position)[:2], [0.5, 0.0])
