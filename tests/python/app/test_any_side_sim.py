"""Grasps from any side, simulated end to end (real MuJoCo physics, OMPL, TOPP-RA): a box
wider than the hand in both horizontal directions, leaning on another, is grasped across its
thickness with a tilted approach, carried and placed in the tray."""

import numpy as np
from scipy.spatial.transform import Rotation

from grasp_pipeline.app.run import run_pipeline
from grasp_pipeline.evaluation.pick_evaluator import in_tray
from grasp_pipeline.orchestration.events import PickEvent
from grasp_pipeline.robot.description import READY_Q
from grasp_pipeline.sim.scene_spec import ObjectSpec, SceneSpec

TABLE_Z_M = 0.2
BOX_M = (0.18, 0.10, 0.035)   # length, width, thickness
LEAN_DEG = 35.0               # placed leaning this much; it settles at about 37°
LOW_EDGE_X_M = 0.64           # the edge on the table, far from the robot: the box rises towards it


def _scene() -> SceneSpec:
    L, _, H = BOX_M
    a = np.radians(LEAN_DEG)
    q = Rotation.from_euler("y", LEAN_DEG, degrees=True).as_quat()
    centre = (LOW_EDGE_X_M - 0.5 * L * np.cos(a) + 0.5 * H * np.sin(a), 0.0,
              TABLE_Z_M + 0.5 * L * np.sin(a) + 0.5 * H * np.cos(a) + 0.003)
    box = ObjectSpec("wide_box", "cuboid", BOX_M, centre, quat_wxyz=(q[3], q[0], q[1], q[2]),
                     rgba=(0.9, 0.5, 0.1, 1.0), category="box")
    support = ObjectSpec("support", "cuboid", (0.03, 0.08, 0.06),
                         (LOW_EDGE_X_M - 0.095, 0.0, TABLE_Z_M + 0.03), rgba=(0.3, 0.3, 0.8, 1.0))
    return SceneSpec("leaning_box", (box, support), TABLE_Z_M, tuple(float(q) for q in READY_Q))


def test_a_wide_box_leaning_on_another_is_grasped_tilted_and_placed_in_the_tray(tmp_path):
    placed = []

    def watch(system):
        system.events.subscribe(PickEvent, lambda ev: placed.append(in_tray(system.world, "wide_box")))

    report = run_pipeline(scene=_scene(), select=[(0.577, 0.0)], out_dir=tmp_path, video=False, prepare=watch)
    (pick,) = report.picks
    assert pick.success and pick.placed and placed == [True], (pick.message, pick.grasp)
    assert pick.grasp["kind"] == "tilted" and pick.grasp["tilt_deg"] >= 30.0, pick.grasp
    assert pick.stall_gap_m < 0.05  # across the 35 mm thickness, not a footprint over 95 mm wide
