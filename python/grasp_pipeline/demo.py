"""``make demo`` / ``grasp-pipeline demo``.

Until the orchestration lands (scan + picks in MuJoCo), the demo runs the
perception core on generated tabletop frames (the reference arrangement of SPEC 8
seen obliquely, then from directly above each object) and prints the table plane
and every object's estimate — what a user checks first on their own clouds.
"""

from __future__ import annotations

import logging

import numpy as np

from .perception import PerceptionSession, load_obb_config, load_scene_filter_config
from .perception.synthetic import look_at, reference_camera_pose, reference_tabletop, render_depth

log = logging.getLogger("grasp_pipeline.demo")

FRAMES_PER_VIEW = 6
FRAME_PERIOD_S = 1.0 / 30.0
PROBE_HEIGHT_ABOVE_TABLE_M = 0.39  # SPEC 8: camera working distance at probing height


def _describe(session: PerceptionSession) -> None:
    plane = session.plane
    print(f"table plane: n = [{plane.n[0]:+.4f}, {plane.n[1]:+.4f}, {plane.n[2]:+.4f}], "
          f"c = {plane.c:+.5f}, height = {plane.height_m:.4f} m, band = {session.band_m:.3f} m")
    for tr in session.tracks():
        e = tr.smoothed
        notes = "; ".join(list(e.notes) + list(e.undetermined_notes)) or "-"
        print(f"  #{tr.tid} {tr.quality.name.lower():7s} centre = ({e.center[0]:.4f}, {e.center[1]:.4f}, "
              f"{e.center[2]:.4f}) m  extents = {e.extents[0] * 1e3:.1f} x {e.extents[1] * 1e3:.1f} x "
              f"{e.extents[2] * 1e3:.1f} mm  theta = {np.degrees(e.theta_rad):.1f} deg  "
              f"pca_tilt = {e.pca_tilt_deg:.1f} deg  grasp_ok = {e.grasp_ok}  notes: {notes}")


def run_demo() -> int:
    session = PerceptionSession(load_scene_filter_config(), load_obb_config())
    scene = reference_tabletop()
    rng = np.random.default_rng(0)
    t = 0.0
    T_ready = reference_camera_pose()
    for _ in range(FRAMES_PER_VIEW):
        pts, _ = render_depth(scene, T_ready, rng=rng)
        session.process(pts, T_ready[:3, 3], t)
        t += FRAME_PERIOD_S
    print("\n== rough view (oblique, from the start pose) ==")
    _describe(session)
    h = session.plane.height_m + PROBE_HEIGHT_ABOVE_TABLE_M
    for tr in session.tracks():
        c = tr.smoothed.center
        T = look_at(eye=np.array([c[0], c[1], h]), target=np.array([c[0], c[1], c[2]]))
        for _ in range(FRAMES_PER_VIEW):
            pts, _ = render_depth(scene, T, rng=rng)
            frame = session.process(pts, T[:3, 3], t)
            t += FRAME_PERIOD_S
        log.info("probe above #%d: %s", tr.tid, session.view_labels(frame))
    print("\n== after probing each object from above ==")
    _describe(session)
    return 0
