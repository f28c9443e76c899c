"""Load point clouds from disk: ``.pcd`` / ``.ply`` with PCL's reader, ``.npy`` with numpy.

``load_cloud(path)`` returns a :class:`Cloud`: ``points`` (N, 3) float32 in the file's own
frame (a camera frame or ``world`` — the file does not say which; the caller knows),
``width`` × ``height`` (``height == 1`` for an unorganized cloud; an organized cloud keeps its
NaN rows so pixel (r, c) is row ``r * width + c``) and ``source_format``.

Supported inputs:

- ``.pcd``: any PCD PCL reads (ascii, binary, binary_compressed); x/y/z of any numeric type.
- ``.ply``: the vertices' x/y/z (ascii or binary PLY); always unorganized.
- ``.npy``: float32/float64 of shape (N, 3) (unorganized) or (H, W, 3) (organized, H×W).

Every failure is an :class:`~grasp_pipeline.exceptions.InputError` whose message names the
file and what is wrong (missing file, unsupported extension, no x/y/z fields, wrong shape…).
ASCII bodies (PCD ``DATA ascii`` and ASCII PLY) are checked line by line before PCL reads
them, because PCL would silently read a non-number as 0 (PCD) or NaN (PLY): a value that is
not a number of its field's type (``nan``/``inf`` are numbers), a line with too few or too
many values, or fewer/more lines than the header declares is an InputError naming the line
number and the field, e.g. ``cloud.pcd: PCD ascii data, line 12: field 'y' (column 2):
'abc' is not a number``.

Before any reader runs, the header's point count is checked against a limit and against the
file's size (:mod:`.cloud_headers`): a header claiming 10^9 points is refused at once.

Finite but absurd coordinates (e.g. 3.4e38) are loaded as they are; the perception core
drops points beyond ``max_abs_coordinate_m`` (scene filter config) like NaN rows.

``save_pcd`` writes (N, 3) or (H, W, 3) points with PCL's writer (default encoding
``binary_compressed``, the compact one PCL tools read).

The PCL part lives in the small extension ``grasp_pipeline._pcl_io`` (linked to
``libpcl_io``), separate from the perception core ``_core`` so that loading the core never
loads PCL-io's VTK dependencies.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..exceptions import InputError
from .cloud_headers import check_cloud_header

SUPPORTED_EXTENSIONS = (".pcd", ".ply", ".npy")
PCD_ENCODINGS = ("binary_compressed", "binary", "ascii")


@dataclass
class Cloud:
    """A point cloud read from a file."""

    points: np.ndarray  # (N, 3) float32; N = width * height; NaN rows kept
    width: int
    height: int
    source_format: str  # "pcd" | "ply" | "npy"
    path: str = ""

    @property
    def organized(self) -> bool:
        return self.height > 1

    @property
    def shape_hw(self) -> tuple[int, int] | None:
        """(H, W) for an organized cloud, else None."""
        return (self.height, self.width) if self.organized else None

    @property
    def num_invalid(self) -> int:
        """Rows with a NaN/Inf coordinate."""
        return int(np.count_nonzero(~np.isfinite(self.points).all(axis=1)))

    @property
    def points_camera_or_world(self) -> np.ndarray:
        """Alias of ``points``: the frame is whatever the file was written in."""
        return self.points

    def grid(self) -> np.ndarray:
        """(H, W, 3) view of an organized cloud ((1, N, 3) for an unorganized one)."""
        return self.points.reshape(self.height, self.width, 3)


def _pcl():
    try:
        from .. import _pcl_io
    except ImportError as exc:  # pragma: no cover - a broken install
        raise InputError(
            "PCD/PLY support needs the extension grasp_pipeline._pcl_io (built with the package "
            f"from cpp/io/ against libpcl_io): {exc}. Reinstall with `pip install .`, or for a "
            "source checkout run `bash scripts/dev_build_core.sh`; .npy files work without it."
        ) from None
    return _pcl_io


def _call(fn, path: str, *args, **kwargs):
    """Run a _pcl_io function, turning its exceptions into InputError."""
    try:
        return fn(path, *args, **kwargs)
    except FileNotFoundError as exc:
        raise InputError(str(exc)) from None
    except (ValueError, TypeError, OSError, RuntimeError) as exc:
        raise InputError(str(exc)) from None


def _load_npy(path: str) -> Cloud:
    if not os.path.isfile(path):
        raise InputError(f"NPY file not found: {path}")
    try:
        arr = np.load(path, allow_pickle=False)
    except Exception as exc:  # numpy raises ValueError/OSError/EOFError… on a bad file
        raise InputError(f"{path}: not a readable .npy file ({exc})") from None
    if not isinstance(arr, np.ndarray) or arr.dtype not in (np.float32, np.float64):
        raise InputError(f"{path}: expected a float32/float64 array, got dtype {arr.dtype} "
                         "(convert with arr.astype(numpy.float32))")
    if arr.ndim == 2 and arr.shape[1] == 3:
        h, w = 1, arr.shape[0]
    elif arr.ndim == 3 and arr.shape[2] == 3:
        h, w = arr.shape[0], arr.shape[1]
    else:
        raise InputError(f"{path}: expected shape (N, 3) or (H, W, 3), got {arr.shape}")
    pts = np.ascontiguousarray(arr.reshape(-1, 3), dtype=np.float32)
    return Cloud(points=pts, width=int(w), height=int(h), source_format="npy", path=path)


def load_cloud(path: str | os.PathLike) -> Cloud:
    """Read a point cloud, dispatching on the extension (``.pcd``, ``.ply``, ``.npy``); the
    header's point count is checked first (:mod:`.cloud_headers`)."""
    path = os.fspath(path)
    ext = Path(path).suffix.lower()
    if ext in SUPPORTED_EXTENSIONS:
        check_cloud_header(path, ext)
    if ext == ".npy":
        return _load_npy(path)
    if ext == ".pcd":
        pts, w, h = _call(_pcl().load_pcd, path)
        return Cloud(points=pts, width=int(w), height=int(h), source_format="pcd", path=path)
    if ext == ".ply":
        pts = _call(_pcl().load_ply, path)
        return Cloud(points=pts, width=int(pts.shape[0]), height=1, source_format="ply", path=path)
    raise InputError(f"{path}: unsupported point-cloud file extension {ext or '(none)'!r}; "
                     f"supported: {', '.join(SUPPORTED_EXTENSIONS)}")


def save_pcd(path: str | os.PathLike, points: np.ndarray, width: int | None = None,
             height: int | None = None, encoding: str = "binary_compressed") -> None:
    """Write points as a PCD file (fields x y z, float32) with PCL's writer.

    ``points`` is (N, 3) — organized if ``width``/``height`` are given (``width × height == N``)
    — or (H, W, 3), which is organized with ``width = W``, ``height = H``.
    """
    path = os.fspath(path)
    if encoding not in PCD_ENCODINGS:
        raise InputError(f"encoding must be one of {', '.join(PCD_ENCODINGS)}, got {encoding!r}")
    arr = np.asarray(points)
    if arr.ndim == 3 and arr.shape[2] == 3:
        if width is None and height is None:
            height, width = arr.shape[0], arr.shape[1]
        arr = arr.reshape(-1, 3)
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise InputError(f"points: expected shape (N, 3) or (H, W, 3), got {arr.shape}")
    if arr.dtype.kind not in "fiu":
        raise InputError(f"points: expected a numeric array, got dtype {arr.dtype}")
    arr = np.ascontiguousarray(arr, dtype=np.float32)
    _call(_pcl().save_pcd, path, arr, width, height, encoding)
