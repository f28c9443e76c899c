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
the plane persistence locks on the first fit (method.md §1.5: with no lock yet, the first fit
becomes the lock), so one ``process`` call yields the plane and every object's estimate. The camera
position used for the view quality (NADIR / OBLIQUE) is the translation of T_world_camera.

Outputs: a human-readable summary on stdout, the JSON report ``--json`` and optionally the
RViz-like PNG ``--png``. No table plane found → :class:`NoTablePlaneError` (exit code 2) with
what to check.
"""

from __future__ import annotations

import logging
import os
import time
from pathlib import Path
from typing import Iterable, Optional, Sequence

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


def _world_transform(T_world_camera, up) -> tuple[np.ndarray, str]:
    if (T_world_camera is None) == (up is None):
        raise InputError("give exactly one of --T-world-camera (16 numbers) or --up X Y Z")
    if T_world_camera is not None:
        return parse_transform(T_world_camera), "T_world_camera"
    return world_from_up(up), "up"


def _load(path) -> tuple[object, float]:
    from .io.cloud_io import load_cloud

    t0 = time.perf_counter()
    cloud = load_cloud(path)
    t_load = time.perf_counter() - t0
    n_valid = len(cloud.points) - cloud.num_invalid
    log.info("loaded %s: %d points (%d invalid)%s in %.0f ms", cloud.path, len(cloud.points),
             cloud.num_invalid, f", organized {cloud.height}x{cloud.width}" if cloud.organized else "",
             1e3 * t_load)
    if n_valid < 3:
        raise InputError(f"{cloud.path}: only {n_valid} valid points; nothing to perceive")
    return cloud, t_load


def _no_plane_error(cloud, pts_world, sf, frame_source: str) -> NoTablePlaneError:
    how = ("the --up vector (world +z expressed in the cloud's frame: it must point away "
           "from the table, towards the camera side)" if frame_source == "up" else
           "--T-world-camera (it maps the cloud's frame into a world frame with z up, "
           "row-major)")
    return NoTablePlaneError(
        f"no table plane found in {cloud.path} ({len(cloud.points) - cloud.num_invalid} valid "
        f"points): no plane within {sf.plane_max_tilt_deg:g} deg of horizontal held at least "
        f"{sf.plane_min_inlier_ratio:g} of the points. Check {how}; check that the "
        f"coordinates are in metres ({_guess_units_hint(pts_world)}); the tolerances are "
        f"--set plane_max_tilt_deg=... and --set plane_dist_thresh=... (now "
        f"{sf.plane_dist_thresh:g} m)")


def _object_entry(i: int, est, view, tid, plane) -> tuple[dict, tuple, Optional[tuple]]:
    """(report entry, box for the snapshot, approach arrow or None) of one estimate."""
    from . import _core

    obj = {"id": i, "track_id": int(tid), "center": _vec(est.center), "extents": _vec(est.extents),
           "theta_deg": float(est.theta_deg), "R_box": np.asarray(est.R_box, float).tolist(),
           "yaw_defined": bool(est.yaw_defined), "grasp_ok": bool(est.grasp_ok),
           "notes": list(est.notes), "undetermined_notes": list(est.undetermined_notes),
           "view": {"quality": view.quality.name.lower(), "angle_deg": float(view.angle_deg)},
           "pca_tilt_deg": float(est.pca_tilt_deg), "num_points": int(est.num_points)}
    arrow = None
    g = _core.best_grasp_from_estimate(est, plane)
    if g is not None:
        Rg = np.asarray(g.R, float)
        obj["grasp"] = {"position": _vec(g.position), "approach": _vec(Rg[:, 0]),
                        "R": Rg.tolist(), "width_m": float(g.width_m)}
        arrow = (np.asarray(g.position, float), Rg[:, 0])
    box = (np.asarray(est.center, float), np.asarray(est.R_box, float), np.asarray(est.extents, float))
    return obj, box, arrow


def _table_inliers(frame) -> Optional[int]:
    planes, idx = frame.raw.filter.planes, frame.raw.filter.table_index
    return int(planes[idx].count_whole) if 0 <= idx < len(planes) else None


def _print_summary(out, report: dict, cloud, view_labels: str) -> None:
    n, pl = report["plane"]["normal"], report["plane"]
    out(f"input: {cloud.path} ({len(cloud.points)} points, {cloud.num_invalid} invalid"
        + (f", organized {cloud.height}x{cloud.width})" if cloud.organized else ")"))
    out(f"table plane: n = ({n[0]:+.4f}, {n[1]:+.4f}, {n[2]:+.4f}), c = {pl['c']:+.4f}, "
        f"height = {pl['height_m']:.4f} m, tilt = {pl['tilt_deg']:.2f} deg"
        + (f", {pl['inliers']} inliers" if pl["inliers"] is not None else ""))
    objects = report["objects"]
    out(f"objects: {len(objects)}" + (f" (views: {view_labels})" if objects else ""))
    for o in objects:
        c, (w, pw, h) = o["center"], o["extents"]
        verdict = "grasp ok" if o["grasp_ok"] else "REFUSED: " + " | ".join(o["notes"])
        out(f"  #{o['id']} {o['view']['quality']:<7} centre ({c[0]:.4f}, {c[1]:.4f}, {c[2]:.4f}) m, "
            f"width {1e3 * w:.1f} x {1e3 * pw:.1f} mm, height {1e3 * h:.1f} mm, "
            f"theta {o['theta_deg']:.1f} deg, pca tilt {o['pca_tilt_deg']:.1f} deg, "
            f"{o['num_points']} pts — {verdict}")
        for note in o["undetermined_notes"]:
            out(f"      note: {note}")


def _report(cloud, T, frame_source, up, frame, plane, objects, settings, timings) -> dict:
    return {
        "input": {"path": str(cloud.path), "format": cloud.source_format, "points": len(cloud.points),
                  "invalid_points": cloud.num_invalid,
                  "out_of_range_points": int(getattr(frame.raw.filter, "num_out_of_range", 0)),
                  "outside_workspace_points": int(frame.outside_workspace),
                  "too_low_clusters": int(frame.raw.filter.num_too_low),
                  "organized": [cloud.height, cloud.width] if cloud.organized else None},
        "world_frame": {"source": frame_source, "T_world_camera": T.tolist(),
                        "up_in_camera": None if up is None else _vec(up)},
        "camera_position": _vec(T[:3, 3]),
        "plane": {"normal": _vec(plane.n), "c": float(plane.c), "height_m": float(plane.height_m),
                  "tilt_deg": float(plane.tilt_deg()), "inliers": _table_inliers(frame)},
        "objects": objects,
        "failed_clusters": [{"label": int(lbl), "why": str(why)}
                            for lbl, why in zip(frame.raw.failed_labels, frame.raw.failures)],
        "timings_ms": timings, "settings": settings.as_dict()}


def _workspace_sets(max_range_m: float | None, crop: Sequence[float] | None) -> list[str]:
    """``--max-range-m`` / ``--crop`` as ``--set`` items of the workspace section (they win
    over ``--config`` and earlier ``--set``); InputError for a value the config refuses."""
    sets = []
    if max_range_m is not None:
        if not (np.isfinite(max_range_m) and max_range_m > 0):
            raise InputError(f"--max-range-m: expected a range > 0 m, got {max_range_m}")
        sets.append(f"workspace.workspace_max_range_m={float(max_range_m)!r}")
    if crop is not None:
        sets.append(f"workspace.workspace_crop_box_m=[{', '.join(repr(float(v)) for v in crop)}]")
    return sets


def run_perceive(path: str | os.PathLike, *, T_world_camera: Sequence | None = None,
                 up: Sequence[float] | None = None, json_path: str | os.PathLike,
                 png_path: str | os.PathLike | None = None, config_file: str | None = None,
                 sets: Sequence[str] = (), out=print, max_range_m: float | None = None,
                 crop: Sequence[float] | None = None) -> dict:
    """Run the ``perceive`` command; returns the JSON report (also written to ``json_path``).

    ``max_range_m`` / ``crop`` (``--max-range-m`` / ``--crop``): the workspace
    (:mod:`~grasp_pipeline.perception.workspace`); points outside it are dropped."""
    from .perception import PerceptionSession
    from .report.serialize import check_writable, write_json
    from .settings import load_settings

    T, frame_source = _world_transform(T_world_camera, up)
    sets = list(sets) + _workspace_sets(max_range_m, crop)
    settings = load_settings(("scene_filter", "obb", "workspace", "depth_noise"), config_file, sets)
    check_writable(json_path, "report file (--json)")
    if png_path is not None:
        check_writable(png_path, "snapshot (--png)")
    cloud, t_load = _load(path)
    pts_world = (cloud.points.astype(np.float64) @ T[:3, :3].T + T[:3, 3]).astype(np.float32)
    session = PerceptionSession(settings.scene_filter, settings.obb, settings.workspace,
                                settings.depth_noise)
    t1 = time.perf_counter()
    # Files go through Euclidean clustering (method.md §1.4), also organized ones: the organized
    # segmentation needs the true camera position, which a file's transform may not give, and
    # it still cuts slivers off steep side faces in some frames.
    frame = session.process(pts_world, camera_position=T[:3, 3].copy(), time_s=0.0)
    if frame.outside_workspace:
        out(f"workspace: dropped {frame.outside_workspace} point(s) outside it")
    timings = {"load": 1e3 * t_load, "perception": 1e3 * (time.perf_counter() - t1)}
    plane = session.plane
    if plane is None:
        raise _no_plane_error(cloud, pts_world, settings.scene_filter, frame_source)
    entries = [_object_entry(i, est, view, tid, plane) for i, (est, view, tid)
               in enumerate(zip(frame.estimates, frame.raw.views, frame.raw.tids))]
    report = _report(cloud, T, frame_source, up, frame, plane, [e[0] for e in entries], settings, timings)
    _print_summary(out, report, cloud, session.view_labels(frame))
    if png_path is not None:
        _snapshot(frame, plane, entries, png_path, cloud, report)
        out(f"snapshot: {png_path}")
    write_json(json_path, report)
    out(f"report: {json_path}")
    return report


def _snapshot(frame, plane, entries, png_path, cloud, report: dict) -> None:
    from .report.snapshot import render_snapshot

    obj_pts, obj_labels = frame.object_points()
    t2 = time.perf_counter()
    render_snapshot(png_path, obj_pts, obj_labels, frame.environment_points(),
                    [e[1] for e in entries], [e[2] for e in entries if e[2] is not None],
                    plane=plane, title=f"perceive {Path(cloud.path).name}")
    report["png"] = str(png_path)
    report["timings_ms"]["png"] = 1e3 * (time.perf_counter() - t2)
