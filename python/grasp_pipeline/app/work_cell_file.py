"""The work-cell description file: a robot's fixed set-up in one YAML file.

What the pipeline needs to know about the cell, in the world frame of the robot base (z up,
metres; every box upright, turned by ``yaw_deg`` about z):

* ``table`` — the box whose top face is the surface objects are picked from (a track over its
  footprint is an object to pick; its top is the table height);
* ``fixtures`` — fixed boxes the arm plans around (the tray's stand, floor and walls), in order;
* ``tray`` — where objects are placed: ``center_m`` (centre of the tray floor's top surface)
  and ``floor`` (the fixture that is its floor; its footprint counts as "in the tray"), or
  ``null`` for a cell without a tray (picks are then not placed);
* ``camera_mount`` — the hand-eye calibration: the camera's optical frame (z forward, x right,
  y down) in the flange frame, ``xyz_m`` and ``rpy_deg`` (roll, pitch, yaw about the fixed x, y,
  z axes, as URDF) or ``quat_xyzw``;
* ``workspace_box_m`` — optional ``[xmin, xmax, ymin, ymax, zmin, zmax]``: points outside are
  dropped before perception (a real camera sees floors and walls); ``[]``: none.

``config/work_cell.yaml`` holds the simulated cell's values (``sim/scene_base.xml``; a test
checks that the cell read from the MuJoCo model equals it) and is the template of a user's file.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Optional

import numpy as np
from scipy.spatial.transform import Rotation

from ..assets import default_config_dir
from ..config import read_yaml
from ..exceptions import ConfigError
from ..messages import brief
from ..motion.occupancy import OrientedBox
from ..motion.work_cell import WorkCell, footprint_distance_m
from ..perception.workspace import WorkspaceConfig

DEFAULT_FILE = "work_cell.yaml"
KEYS = ("table", "fixtures", "tray", "camera_mount", "workspace_box_m")
BOX_KEYS = ("name", "center_m", "size_m", "yaw_deg")
#: No coordinate or size of a tabletop cell is this large [m] (larger: millimetres?).
MAX_COORDINATE_M = 10.0
#: A camera on the hand is nearer the flange than this [m].
MAX_MOUNT_OFFSET_M = 0.5
#: The tray centre lies on its floor's top surface, within this [m].
TRAY_FLOOR_TOL_M = 0.01


@dataclass(frozen=True)
class WorkCellSetup:
    """A loaded work-cell file: the :class:`~grasp_pipeline.motion.work_cell.WorkCell` (table,
    fixtures, tray), the camera mount ``flange_T_camera`` (4, 4), the perception crop box and
    the fixtures' names (in the order of ``cell.fixtures``)."""

    cell: WorkCell
    flange_T_camera: np.ndarray
    workspace_box_m: tuple[float, ...] = ()
    fixture_names: tuple[str, ...] = ()
    source: str = ""

    @property
    def table_top_z_m(self) -> float:
        """Height of the table surface [m]."""
        t = self.cell.table
        return float(t.center[2] + 0.5 * np.abs(np.asarray(t.R)[2]) @ np.asarray(t.extents))

    def workspace(self) -> WorkspaceConfig:
        """The perception crop of the cell (off without a ``workspace_box_m``)."""
        return WorkspaceConfig(workspace_crop_box_m=tuple(self.workspace_box_m))


def default_work_cell_path() -> Path:
    """``config/work_cell.yaml`` shipped with the package: the simulated cell."""
    return default_config_dir() / DEFAULT_FILE


def load_work_cell(path: str | Path | None = None) -> WorkCellSetup:
    """Read and check a work-cell file (default: the simulated cell's); a bad file raises a
    :class:`~grasp_pipeline.exceptions.ConfigError` naming the file and the entry."""
    path = Path(path) if path is not None else default_work_cell_path()
    if not path.exists():
        raise ConfigError(f"work cell file {path} not found; start from a copy of "
                          f"{default_work_cell_path()} (docs/real_robot.md)")
    return parse_work_cell(read_yaml(path), str(path))


def parse_work_cell(data: dict, source: str = "work cell") -> WorkCellSetup:
    """The :class:`WorkCellSetup` of a mapping laid out like ``config/work_cell.yaml``."""
    _known(data, KEYS, source, "")
    for key in ("table", "fixtures", "camera_mount"):
        if key not in data:
            raise ConfigError(f"{source}: {key} is missing (see {default_work_cell_path()})")
    table = _box(data["table"], source, "table", named=False)
    named = _fixtures(data["fixtures"], source)
    names = tuple(n for n, _ in named)
    fixtures = tuple(b for _, b in named)
    center, floor = _tray(data.get("tray"), dict(named), source)
    mount = _mount(data["camera_mount"], source)
    box = _numbers(data.get("workspace_box_m") or [], source, "workspace_box_m", None)
    if box and (len(box) != 6 or any(box[2 * a] >= box[2 * a + 1] for a in range(3))):
        raise ConfigError(f"{source}: workspace_box_m must be [xmin, xmax, ymin, ymax, zmin, zmax] in m, "
                          f"each minimum below its maximum (or [] for none), got {brief(list(box))}")
    return WorkCellSetup(WorkCell(table, fixtures, center, floor), mount, tuple(box), names, source)


def _known(data: Any, keys: tuple, source: str, where: str) -> None:
    label = where.rstrip(".") or "the file"
    if not isinstance(data, dict):
        raise ConfigError(f"{source}: {label} must be a mapping of name: value, got {brief(data)}")
    unknown = sorted(str(k) for k in data if k not in keys)
    if unknown:
        raise ConfigError(f"{source}: unknown entr{'y' if len(unknown) == 1 else 'ies'} "
                          f"{', '.join(where + u for u in unknown)}; known: {', '.join(where + k for k in keys)}")


def _numbers(value: Any, source: str, key: str, n: Optional[int]) -> tuple[float, ...]:
    """``value`` as ``n`` finite numbers in metres (or degrees) of a tabletop cell."""
    ok = isinstance(value, (list, tuple)) and (n is None or len(value) == n) and all(
        isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in value)
    if not ok:
        what = f"{n} numbers" if n is not None else "a list of numbers"
        raise ConfigError(f"{source}: {key} must be {what}, got {brief(value)}")
    out = tuple(float(v) for v in value)
    if key.endswith("_m") and any(abs(v) > MAX_COORDINATE_M for v in out):
        raise ConfigError(f"{source}: {key} = {brief(list(out))} is more than {MAX_COORDINATE_M:.0f} m — "
                          "millimetres? The work cell is in metres")
    return out


def _box(data: Any, source: str, where: str, named: bool = True) -> OrientedBox:
    _known(data, BOX_KEYS if named else BOX_KEYS[1:], source, f"{where}.")
    for key in ("center_m", "size_m"):
        if key not in data:
            raise ConfigError(f"{source}: {where}.{key} is missing")
    center = np.array(_numbers(data["center_m"], source, f"{where}.center_m", 3))
    size = np.array(_numbers(data["size_m"], source, f"{where}.size_m", 3))
    if np.any(size <= 0):
        raise ConfigError(f"{source}: {where}.size_m must be positive (full sizes in m), got {size.tolist()}")
    yaw = math.radians(_numbers([data.get("yaw_deg", 0.0)], source, f"{where}.yaw_deg", 1)[0])
    c, s = math.cos(yaw), math.sin(yaw)
    return OrientedBox(center, np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]), size)


def _fixtures(data: Any, source: str) -> list[tuple[str, OrientedBox]]:
    if not isinstance(data, list):
        raise ConfigError(f"{source}: fixtures must be a list of boxes ({{name, center_m, size_m}}), "
                          f"or [] for none; got {brief(data)}")
    out = []
    for i, item in enumerate(data):
        name = item.get("name") if isinstance(item, dict) else None
        if not isinstance(name, str) or not name or name in dict(out):
            raise ConfigError(f"{source}: fixtures[{i}] needs a name of its own (a text), got {brief(name)}")
        out.append((name, _box(item, source, f"fixtures[{i}]")))
    return out


def _tray(data: Any, fixtures: dict, source: str) -> tuple[Optional[np.ndarray], Optional[OrientedBox]]:
    if data is None:
        return None, None
    _known(data, ("center_m", "floor"), source, "tray.")
    floor = fixtures.get(data.get("floor"))
    if floor is None:
        raise ConfigError(f"{source}: tray.floor must name one of the fixtures ({', '.join(fixtures) or 'none'}), "
                          f"got {brief(data.get('floor'))}")
    center = np.array(_numbers(data.get("center_m"), source, "tray.center_m", 3))
    top = float(floor.center[2] + 0.5 * floor.extents[2])
    if footprint_distance_m(floor, center[:2]) > 0.0 or abs(center[2] - top) > TRAY_FLOOR_TOL_M:
        raise ConfigError(f"{source}: tray.center_m {center.tolist()} must lie on the top of its floor "
                          f"{data['floor']!r} (over its footprint, z = {top:.3f} m)")
    return center, floor


def _mount(data: Any, source: str) -> np.ndarray:
    _known(data, ("xyz_m", "rpy_deg", "quat_xyzw"), source, "camera_mount.")
    if ("rpy_deg" in data) == ("quat_xyzw" in data):
        raise ConfigError(f"{source}: camera_mount needs exactly one of rpy_deg (roll, pitch, yaw about "
                          "the fixed x, y, z axes) and quat_xyzw")
    xyz = np.array(_numbers(data.get("xyz_m"), source, "camera_mount.xyz_m", 3))
    if np.linalg.norm(xyz) > MAX_MOUNT_OFFSET_M:
        raise ConfigError(f"{source}: camera_mount.xyz_m puts the camera {np.linalg.norm(xyz):.2f} m from the "
                          f"flange (at most {MAX_MOUNT_OFFSET_M} m on a hand) — millimetres, or the camera "
                          "in the base frame? Give the flange-to-camera translation in metres")
    if "rpy_deg" in data:
        R = Rotation.from_euler("xyz", _numbers(data["rpy_deg"], source, "camera_mount.rpy_deg", 3), degrees=True)
    else:
        q = np.array(_numbers(data["quat_xyzw"], source, "camera_mount.quat_xyzw", 4))
        if abs(np.linalg.norm(q) - 1.0) > 1e-3:
            raise ConfigError(f"{source}: camera_mount.quat_xyzw must be a unit quaternion (x, y, z, w), "
                              f"its norm is {np.linalg.norm(q):.4f}")
        R = Rotation.from_quat(q)
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R.as_matrix(), xyz
    return T
