"""``grasp-pipeline perceive``: one real point cloud from disk through the perception core.

The cloud (``.pcd`` / ``.ply`` / ``.npy``, see :mod:`grasp_pipeline.io.cloud_io`) is in the
camera frame (or any frame) given by the file; the user says where ``world`` is:

- ``--T-world-camera`` 16 numbers, row-major 4×4: ``p_world = R p_file + t``. It must be a
  rigid transform: last row ``0 0 0 1``, ``R`` orthonormal within 1e-3 (rounded numbers pasted
  from a log are accepted and re-orthonormalised with an SVD) and ``det R = +1``.
- ``--up X Y Z``: the direction of world +z *in the file's frame* (e.g. the gravity vector
  reversed, from an IMU). The world frame is then built with its origin at the file frame's
  origin (the camera), ``z`` = the normalised up vector, ``x`` = the file frame's x axis
  projected into the plane perpendicular to ``z`` (the file's y axis projected when x is
  within 1e-6 of parallel to up), ``y = z × x``. The table is then nearly horizontal, so the
  usual tilt limit (``plane_max_tilt_deg``) finds it; its ``height_m`` is negative (below the
  camera).

Exactly one frame is processed with :class:`~grasp_pipeline.perception.PerceptionSession`:
the plane persistence locks on the first fit (SPEC 1.5: "No lock yet: first fit becomes
lock"), so one ``process`` call yields the plane and every object's estimate. The camera
position used for the view quality (NADIR / OBLIQUE) is the translation of T_world_camera.

Outputs: a human-readable summary on stdout, the JSON report ``--json`` and optionally the
RViz-like PNG ``--png``. No table plane found → :class:`NoTablePlaneError` (exit code 2) with
what to check.
"""

from __future__ import annotations

import json
import logging
import math
import os
import time
from pathlib import Path
from typing import Iterable, Sequence

import numpy as np

from .exceptions import GraspPipelineError, InputError

log = logging.getLogger("grasp_pipeline.perceive")


class NoTablePlaneError(GraspPipelineError):
    """No horizontal table plane was found in the cloud."""


# ---- world frame -------------------------------------------------------------------
def parse_transform(values: Iterable, *, tol: float = 1e-3) -> np.ndarray:
    """16 numbers (row-major) -> a validated rigid 4×4 transform (InputError otherwise).

    Accepts a flat sequence of numbers or strings (also comma-separated strings).
    """
    flat: list[str | float] = []
    for v in values:
        if isinstance(v, str):
            flat += [t for t in v.replace(",", " ").split() if t]
        else:
            flat.append(v)
    if len(flat) != 16:
        raise InputError(f"--T-world-camera: expected 16 numbers (a 4x4 matrix, row-major), "
                         f"got {len(flat)}")
    try:
        T = np.array([float(v) for v in flat], dtype=float).reshape(4, 4)
    except ValueError as exc:
        raise InputError(f"--T-world-camera: not a number ({exc})") from None
    if not np.isfinite(T).all():
        raise InputError("--T-world-camera: all 16 numbers must be finite")
    if np.abs(T[3] - [0.0, 0.0, 0.0, 1.0]).max() > 1e-9:
        raise InputError(f"--T-world-camera: the last row must be 0 0 0 1, got "
                         f"{' '.join(f'{v:g}' for v in T[3])} (a rigid transform, row-major)")
    R = T[:3, :3]
    err = float(np.abs(R.T @ R - np.eye(3)).max())
    if err > tol:
        raise InputError(f"--T-world-camera: the rotation part is not orthonormal "
                         f"(max |R^T R - I| = {err:.3g} > {tol:g}); give a rigid transform "
                         "(rotation + translation, no scale or shear), row-major")
    if np.linalg.det(R) < 0:
        raise InputError("--T-world-camera: the rotation has det = -1 (a reflection); "
                         "rotations must be right-handed")
    U, _, Vt = np.linalg.svd(R)
    T[:3, :3] = U @ Vt
    return T


def world_from_up(up: Sequence[float]) -> np.ndarray:
    """T_world_camera whose z axis is ``up`` (given in the camera/file frame); see module doc."""
    try:
        z = np.asarray([float(v) for v in up], dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"--up: expected 3 numbers, got {up!r}") from None
    if z.shape != (3,) or not np.isfinite(z).all():
        raise InputError(f"--up: expected 3 finite numbers, got {list(up)}")
    norm = np.linalg.norm(z)
    if norm < 1e-9:
        raise InputError("--up: the up vector must not be zero")
    z = z / norm
    x = None
    for axis in (np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])):
        proj = axis - (axis @ z) * z
        if np.linalg.norm(proj) > 1e-6:
            x = proj / np.linalg.norm(proj)
            break
    assert x is not None  # x and y cannot both be parallel to z
    y = np.cross(z, x)
    T = np.eye(4)
    T[:3, :3] = np.vstack([x, y, z])  # rows: world axes in camera coordinates
    return T


# ---- the command ---------------------------------------------------------------------
def _vec(v) -> list[float]:
    return [float(x) for x in np.asarray(v, dtype=float).reshape(-1)]


def _guess_units_hint(points_world: np.ndarray) -> str:
    finite = points_world[np.isfinite(points_world).all(axis=1)]
    if len(finite) == 0:
        return "the cloud has no valid (finite) points"
    med = float(np.median(np.linalg.norm(finite, axis=1)))
    if med > 20.0:
        return (f"the points are {med:.0f} units from the origin on median — millimetres? "
                "the pipeline expects metres (divide by 1000)")
    return f"median distance of the points from the origin: {med:.2f} m"


def run_perceive(path: str | os.PathLike, *, T_world_camera: Sequence | None = None,
                 up: Sequence[float] | None = None, json_path: str | os.PathLike,
                 png_path: str | os.PathLike | None = None, config_file: str | None = None,
                 sets: Sequence[str] = (), out=print) -> dict:
    """Run the ``perceive`` command; returns the JSON report (also written to ``json_path``)."""
    from . import _core
    from .io.cloud_io import load_cloud
    from .perception import PerceptionSession
    from .settings import load_settings

    if (T_world_camera is None) == (up is None):
        raise InputError("give exactly one of --T-world-camera (16 numbers) or --up X Y Z")
    settings = load_settings(("scene_filter", "obb"), config_file, sets)
    if T_world_camera is not None:
        T = parse_transform(T_world_camera)
        frame_source = "T_world_camera"
    else:
        T = world_from_up(up)
        frame_source = "up"

    t0 = time.perf_counter()
    cloud = load_cloud(path)
    t_load = time.perf_counter() - t0
    n_total = len(cloud.points)
    n_invalid = cloud.num_invalid
    log.info("loaded %s: %d points (%d invalid)%s in %.0f ms", cloud.path, n_total, n_invalid,
             f", organized {cloud.height}x{cloud.width}" if cloud.organized else "", 1e3 * t_load)
    if n_total - n_invalid < 3:
        raise InputError(f"{cloud.path}: only {n_total - n_invalid} valid points; nothing to perceive")

    R, t = T[:3, :3], T[:3, 3]
    pts_world = (cloud.points.astype(np.float64) @ R.T + t).astype(np.float32)
    camera_position = t.copy()

    session = PerceptionSession(settings.scene_filter, settings.obb)
    t1 = time.perf_counter()
    frame = session.process(pts_world, camera_position=camera_position, time_s=0.0)
    t_perc = time.perf_counter() - t1
    plane = session.plane
    if plane is None:
        sf = settings.scene_filter
        how = ("the --up vector (world +z expressed in the cloud's frame: it must point away "
               "from the table, towards the camera side)" if frame_source == "up" else
               "--T-world-camera (it maps the cloud's frame into a world frame with z up, "
               "row-major)")
        raise NoTablePlaneError(
            f"no table plane found in {cloud.path} ({n_total - n_invalid} valid points): no "
            f"plane within {sf.plane_max_tilt_deg:g} deg of horizontal held at least "
            f"{sf.plane_min_inlier_ratio:g} of the points. Check {how}; check that the "
            f"coordinates are in metres ({_guess_units_hint(pts_world)}); the tolerances are "
            f"--set plane_max_tilt_deg=... and --set plane_dist_thresh=... (now "
            f"{sf.plane_dist_thresh:g} m)")

    table_inliers = None
    planes = frame.raw.filter.planes
    idx = frame.raw.filter.table_index
    if 0 <= idx < len(planes):
        table_inliers = int(planes[idx].count_whole)

    objects = []
    boxes, grasps = [], []
    for i, (est, view, tid) in enumerate(zip(frame.estimates, frame.raw.views, frame.raw.tids)):
        w, pw, h = _vec(est.extents)
        obj = {
            "id": i,
            "track_id": int(tid),
            "center": _vec(est.center),
            "extents": [w, pw, h],
            "theta_deg": float(est.theta_deg),
            "R_box": np.asarray(est.R_box, float).tolist(),
            "yaw_defined": bool(est.yaw_defined),
            "grasp_ok": bool(est.grasp_ok),
            "notes": list(est.notes),
            "undetermined_notes": list(est.undetermined_notes),
            "view": {"quality": view.quality.name.lower(), "angle_deg": float(view.angle_deg)},
            "pca_tilt_deg": float(est.pca_tilt_deg),
            "num_points": int(est.num_points),
        }
        g = _core.best_grasp_from_estimate(est, plane)
        if g is not None:
            Rg = np.asarray(g.R, float)
            obj["grasp"] = {"position": _vec(g.position), "approach": _vec(Rg[:, 0]),
                            "R": Rg.tolist(), "width_m": float(g.width_m)}
            grasps.append((np.asarray(g.position, float), Rg[:, 0]))
        objects.append(obj)
        boxes.append((np.asarray(est.center, float), np.asarray(est.R_box, float),
                      np.asarray(est.extents, float)))

    report = {
        "input": {
            "path": str(cloud.path),
            "format": cloud.source_format,
            "points": n_total,
            "invalid_points": n_invalid,
            "organized": [cloud.height, cloud.width] if cloud.organized else None,
        },
        "world_frame": {"source": frame_source, "T_world_camera": T.tolist(),
                        "up_in_camera": None if up is None else _vec(up)},
        "camera_position": _vec(camera_position),
        "plane": {"normal": _vec(plane.n), "c": float(plane.c), "height_m": float(plane.height_m),
                  "tilt_deg": float(plane.tilt_deg()), "inliers": table_inliers},
        "objects": objects,
        "failed_clusters": [{"label": int(lbl), "why": str(why)}
                            for lbl, why in zip(frame.raw.failed_labels, frame.raw.failures)],
        "timings_ms": {"load": 1e3 * t_load, "perception": 1e3 * t_perc},
        "settings": settings.as_dict(),
    }

    # ---- human-readable summary ----
    n = plane.n
    out(f"input: {cloud.path} ({n_total} points, {n_invalid} invalid"
        + (f", organized {cloud.height}x{cloud.width})" if cloud.organized else ")"))
    out(f"table plane: n = ({n[0]:+.4f}, {n[1]:+.4f}, {n[2]:+.4f}), c = {plane.c:+.4f}, "
        f"height = {plane.height_m:.4f} m, tilt = {plane.tilt_deg():.2f} deg"
        + (f", {table_inliers} inliers" if table_inliers is not None else ""))
    out(f"objects: {len(objects)}" + (f" (views: {session.view_labels(frame)})" if objects else ""))
    for o in objects:
        c, (w, pw, h) = o["center"], o["extents"]
        verdict = "grasp ok" if o["grasp_ok"] else "REFUSED: " + " | ".join(o["notes"])
        out(f"  #{o['id']} {o['view']['quality']:<7} centre ({c[0]:.4f}, {c[1]:.4f}, {c[2]:.4f}) m, "
            f"width {1e3 * w:.1f} x {1e3 * pw:.1f} mm, height {1e3 * h:.1f} mm, "
            f"theta {o['theta_deg']:.1f} deg, pca tilt {o['pca_tilt_deg']:.1f} deg, "
            f"{o['num_points']} pts — {verdict}")
        for note in o["undetermined_notes"]:
            out(f"      note: {note}")

    if png_path is not None:
        from .report.snapshot import render_snapshot

        obj_pts, obj_labels = frame.object_points()
        t2 = time.perf_counter()
        render_snapshot(png_path, obj_pts, obj_labels, frame.environment_points(), boxes, grasps,
                        plane=plane, title=f"perceive {Path(cloud.path).name}")
        report["png"] = str(png_path)
        report["timings_ms"]["png"] = 1e3 * (time.perf_counter() - t2)
        out(f"snapshot: {png_path}")

    json_path = Path(json_path)
    if json_path.parent and not json_path.parent.exists():
        json_path.parent.mkdir(parents=True, exist_ok=True)
    with open(json_path, "w", encoding="utf-8") as fh:
        json.dump(_jsonable(report), fh, indent=2)
    out(f"report: {json_path}")
    return report


def _jsonable(obj):
    """Replace non-finite floats (not valid JSON) by None, recursively."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    return obj
