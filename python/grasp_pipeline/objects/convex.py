"""Convex collision parts for a mesh: one hull per body, or a CoACD decomposition (cached on disk).

MuJoCo collides convex meshes only, so an object is a set of convex parts whose union is the
object. :func:`convex_parts` takes the bodies of a collision mesh (the ``o``/``g`` groups of an
OBJ, else its connected pieces):

* several bodies (VGN/GIGA collision files are decomposed that way): each body's convex hull is
  one part — except a closed body that is clearly not convex, which is decomposed like below;
* one body: its hull when it is convex (closed, volume >= ``convex_volume_ratio`` of its hull),
  else a CoACD decomposition (``pip install '.[meshes]'``), cached under
  :data:`DEFAULT_CACHE_DIR` by the sha256 of the mesh arrays and the parameters. Without
  ``coacd`` it warns once and uses the single convex hull.

Afterwards parts below ``min_part_volume_fraction`` of the total are dropped and the rest are
merged (the pair whose joint hull adds the least volume first) down to ``max_parts`` — every part
is a MuJoCo geom and costs collision time.
"""

from __future__ import annotations

import hashlib
import logging
import os
import tempfile
import time
import warnings
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Callable, Optional, Sequence

import numpy as np
import trimesh

from .model import MeshError

log = logging.getLogger(__name__)

#: Where decompositions are cached unless a ``cache_dir`` is given (``~`` expanded when used).
DEFAULT_CACHE_DIR = "~/.cache/grasp_pipeline/convex"
#: Bumped whenever the cached content or the way it is computed changes.
CACHE_VERSION = 1
#: Most convex parts one object may have (each is one MuJoCo geom).
MAX_PARTS = 32
#: A part smaller than this fraction of the object's total part volume is dropped.
MIN_PART_VOLUME_FRACTION = 1e-3
#: A closed body whose volume is at least this fraction of its hull's counts as convex.
CONVEX_VOLUME_RATIO = 0.97
#: A hull with less volume than this fraction of (its largest extent)^3 is flat (not a part).
FLAT_VOLUME_RATIO = 1e-6
#: What to install for the decomposition.
INSTALL_HINT = "pip install '.[meshes]'"

_warned_no_coacd = False


@dataclass(frozen=True)
class DecompositionParams:
    """How collision parts are made; CoACD's own settings keep CoACD's names."""

    threshold: float = 0.05           # CoACD concavity threshold (smaller: more, tighter parts)
    max_parts: int = MAX_PARTS
    resolution: int = 2000            # CoACD sampling resolution
    preprocess_mode: str = "auto"     # CoACD manifold pre-processing: "auto", "on", "off"
    preprocess_resolution: int = 50
    mcts_nodes: int = 20
    mcts_iterations: int = 150
    mcts_max_depth: int = 3
    seed: int = 0
    min_part_volume_fraction: float = MIN_PART_VOLUME_FRACTION
    convex_volume_ratio: float = CONVEX_VOLUME_RATIO

    def __post_init__(self) -> None:
        if not 0 < self.threshold <= 1:
            raise MeshError(f"convex decomposition: threshold must be in (0, 1], got {self.threshold}")
        if self.max_parts < 1:
            raise MeshError(f"convex decomposition: max_parts must be >= 1, got {self.max_parts}")
        if self.preprocess_mode not in ("auto", "on", "off"):
            raise MeshError("convex decomposition: preprocess_mode must be 'auto', 'on' or 'off', "
                            f"got {self.preprocess_mode!r}")


@dataclass(frozen=True)
class ConvexResult:
    """The parts, how they were made (``"hull"``, ``"bodies"``, ``"coacd"``, ``"cache"``,
    ``"hull-no-coacd"``), notes for the user and the seconds it took."""

    parts: tuple
    method: str
    notes: tuple[str, ...]
    seconds: float


# ----------------------------------------------------------------------------------- hulls


def hull_of(mesh_or_points) -> Optional[trimesh.Trimesh]:
    """The convex hull (closed, outward-facing) of a mesh's vertices or of an (n, 3) point array,
    or None when it is flat or degenerate (volume <= ``FLAT_VOLUME_RATIO`` * extent^3)."""
    pts = np.asarray(getattr(mesh_or_points, "vertices", mesh_or_points), dtype=np.float64)
    if len(pts) < 4 or not np.isfinite(pts).all():
        return None
    try:
        hull = trimesh.convex.convex_hull(pts)
    except Exception:  # qhull refuses flat or collinear point sets
        return None
    extent = float(np.max(pts.max(axis=0) - pts.min(axis=0)))
    if not hull.is_watertight or not hull.volume > FLAT_VOLUME_RATIO * extent ** 3:
        return None
    return hull


def is_convex_body(mesh: trimesh.Trimesh, ratio: float = CONVEX_VOLUME_RATIO,
                   hull: Optional[trimesh.Trimesh] = None) -> bool:
    """Closed, and its volume is at least ``ratio`` of its hull's (``hull`` if already known)."""
    if not mesh.is_watertight:
        return False
    hull = hull if hull is not None else hull_of(mesh)
    return hull is not None and abs(mesh.volume) >= ratio * hull.volume


# ----------------------------------------------------------------------------------- cache


def cache_key(mesh: trimesh.Trimesh, params: DecompositionParams) -> str:
    """sha256 of the mesh arrays, the parameters and :data:`CACHE_VERSION`."""
    h = hashlib.sha256()
    h.update(f"grasp_pipeline.convex v{CACHE_VERSION} {sorted(asdict(params).items())}".encode())
    h.update(np.ascontiguousarray(mesh.vertices, dtype="<f8").tobytes())
    h.update(np.ascontiguousarray(mesh.faces, dtype="<i8").tobytes())
    return h.hexdigest()


def _cache_path(cache_dir: Optional[os.PathLike], key: str) -> Path:
    base = Path(os.path.expanduser(str(cache_dir if cache_dir is not None else DEFAULT_CACHE_DIR)))
    return base / f"{key}.npz"


def _pack(parts: Sequence[trimesh.Trimesh]) -> dict:
    return {"vertices": np.concatenate([p.vertices for p in parts]).astype(np.float64),
            "faces": np.concatenate([p.faces for p in parts]).astype(np.int64),
            "n_vertices": np.array([len(p.vertices) for p in parts], dtype=np.int64),
            "n_faces": np.array([len(p.faces) for p in parts], dtype=np.int64)}


def _unpack(arrays) -> tuple:
    v_end, f_end = np.cumsum(arrays["n_vertices"]), np.cumsum(arrays["n_faces"])
    parts = []
    for i in range(len(v_end)):
        v0 = v_end[i - 1] if i else 0
        f0 = f_end[i - 1] if i else 0
        parts.append(trimesh.Trimesh(arrays["vertices"][v0:v_end[i]],
                                     arrays["faces"][f0:f_end[i]], process=False))
    return tuple(parts)


def _read_cache(path: Path) -> Optional[tuple]:
    if not path.is_file():
        return None
    try:
        with np.load(path, allow_pickle=False) as data:
            parts = _unpack(data)
    except Exception as exc:  # a truncated or foreign file: recompute and overwrite it
        log.warning("convex cache %s is unreadable (%s); recomputing", path, exc)
        return None
    return parts if parts else None


def _write_cache(path: Path, parts: Sequence[trimesh.Trimesh]) -> None:
    """Atomic write (temporary file + rename), so concurrent loaders never see half a file."""
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=".tmp-", suffix=".npz")
        with os.fdopen(fd, "wb") as fh:
            np.savez(fh, **_pack(parts))
        os.replace(tmp, path)
    except OSError as exc:
        log.warning("cannot write the convex cache %s (%s); the decomposition is not kept", path, exc)


# ----------------------------------------------------------------------------------- coacd


def _import_coacd():
    """The ``coacd`` module, or None (warned once per process) when it is not installed."""
    global _warned_no_coacd
    try:
        import coacd  # optional extra: pip install '.[meshes]'
    except ImportError:
        if not _warned_no_coacd:
            _warned_no_coacd = True
            warnings.warn("coacd is not installed, so non-convex meshes collide as their single "
                          f"convex hull (too big where the object is hollow or bent); "
                          f"{INSTALL_HINT} to decompose them", RuntimeWarning, stacklevel=3)
        return None
    return coacd


def _run_coacd(coacd, mesh: trimesh.Trimesh, params: DecompositionParams) -> list:
    coacd.set_log_level("error")
    pieces = coacd.run_coacd(
        coacd.Mesh(np.asarray(mesh.vertices, dtype=np.float64), np.asarray(mesh.faces, dtype=np.int32)),
        threshold=params.threshold, max_convex_hull=params.max_parts,
        preprocess_mode=params.preprocess_mode, preprocess_resolution=params.preprocess_resolution,
        resolution=params.resolution, mcts_nodes=params.mcts_nodes,
        mcts_iterations=params.mcts_iterations, mcts_max_depth=params.mcts_max_depth,
        seed=params.seed)
    return [h for h in (hull_of(trimesh.Trimesh(v, f)) for v, f in pieces) if h is not None]


def decompose(mesh: trimesh.Trimesh, params: DecompositionParams = DecompositionParams(), *,
              cache_dir: Optional[os.PathLike] = None, source: str = "") -> ConvexResult:
    """Convex parts of one non-convex body: the cache, else CoACD (then cached), else its hull."""
    t0 = time.perf_counter()
    path = _cache_path(cache_dir, cache_key(mesh, params))
    cached = _read_cache(path)
    if cached is not None:
        return ConvexResult(cached, "cache", (f"{len(cached)} convex parts (cached decomposition)",),
                            time.perf_counter() - t0)
    coacd = _import_coacd()
    hull = hull_of(mesh)
    if coacd is None:
        parts = () if hull is None else (hull,)
        return ConvexResult(parts, "hull-no-coacd", (f"not convex, but coacd is not installed: one convex "
                                                     f"hull ({INSTALL_HINT})",), time.perf_counter() - t0)
    try:
        pieces = _run_coacd(coacd, mesh, params)
    except Exception as exc:  # CoACD failing on a bad mesh must not lose the object
        log.warning("%s: coacd failed (%s); using the convex hull", source or "mesh", exc)
        pieces = []
    if not pieces:
        parts = () if hull is None else (hull,)
        return ConvexResult(parts, "hull", ("coacd gave no parts: one convex hull",), time.perf_counter() - t0)
    parts, notes = limit_parts(pieces, params)
    parts = _unpack(_pack(parts))  # exactly what a cached load returns
    _write_cache(path, parts)
    return ConvexResult(parts, "coacd", (f"decomposed by coacd into {len(parts)} convex parts",) + notes,
                        time.perf_counter() - t0)


# ----------------------------------------------------------------------------------- limits


def _merge_cost(a: trimesh.Trimesh, b: trimesh.Trimesh) -> tuple[float, Optional[trimesh.Trimesh]]:
    joint = hull_of(np.vstack([a.vertices, b.vertices]))
    if joint is None:
        return float("inf"), None
    return joint.volume - a.volume - b.volume, joint


def _merge_smallest(parts: list, candidates: int = 8) -> None:
    """Merge the smallest part with the nearby part whose joint hull adds the least volume."""
    i = int(np.argmin([p.volume for p in parts]))
    centre = parts[i].bounds.mean(axis=0)
    gaps = [np.linalg.norm(p.bounds.mean(axis=0) - centre) if j != i else np.inf for j, p in enumerate(parts)]
    best = (float("inf"), None, -1)
    for j in np.argsort(gaps)[:candidates]:
        cost, joint = _merge_cost(parts[i], parts[j])
        if joint is not None and cost < best[0]:
            best = (cost, joint, int(j))
    if best[1] is None:  # nothing merges (should not happen with solid parts): drop the smallest
        parts.pop(i)
        return
    parts[best[2]] = best[1]
    parts.pop(i)


def limit_parts(parts: Sequence[trimesh.Trimesh], params: DecompositionParams = DecompositionParams()
                ) -> tuple[tuple, tuple[str, ...]]:
    """Drop tiny parts, then merge down to ``params.max_parts``; returns (parts, notes)."""
    parts = list(parts)
    notes = []
    total = sum(p.volume for p in parts)
    keep = [p for p in parts if p.volume >= params.min_part_volume_fraction * total]
    if len(keep) < len(parts):
        notes.append(f"dropped {len(parts) - len(keep)} tiny parts "
                     f"(< {params.min_part_volume_fraction:g} of the volume)")
    if len(keep) > params.max_parts:
        n = len(keep)
        while len(keep) > params.max_parts:
            _merge_smallest(keep)
        notes.append(f"merged {n} parts into {len(keep)} (max_parts={params.max_parts})")
    return tuple(keep), tuple(notes)


# ----------------------------------------------------------------------------------- entry


def _body_parts(body: trimesh.Trimesh, params: DecompositionParams, decomp: Callable,
                alone: bool) -> tuple[list, list]:
    """Parts of one body and notes: its hull when convex (or an open piece among several)."""
    hull = hull_of(body)
    if is_convex_body(body, params.convex_volume_ratio, hull) or (not alone and not body.is_watertight):
        return ([hull] if hull is not None else []), ([] if hull is not None else ["a flat body was skipped"])
    res = decomp(body)
    return list(res.parts), list(res.notes)


def convex_parts(bodies: Sequence[trimesh.Trimesh], params: DecompositionParams = DecompositionParams(),
                 *, cache_dir: Optional[os.PathLike] = None, source: str = "") -> ConvexResult:
    """Convex collision parts for the bodies of one collision mesh (see the module docstring).

    Raises :class:`MeshError` (naming ``source``) when no part with a positive volume is left."""
    t0 = time.perf_counter()
    methods = set()
    if not bodies or hull_of(np.vstack([b.vertices for b in bodies])) is None:
        raise MeshError(f"{source or 'mesh'}: no collision part with a positive volume "
                        "(the mesh is flat or degenerate)")

    def decomp(body):
        res = decompose(body, params, cache_dir=cache_dir, source=source)
        methods.add(res.method)
        return res

    parts, notes = [], []
    for body in bodies:
        p, n = _body_parts(body, params, decomp, alone=len(bodies) == 1)
        parts += p
        notes += n
    if not parts:
        raise MeshError(f"{source or 'mesh'}: no collision part with a positive volume "
                        "(the mesh is flat or degenerate)")
    if len(bodies) > 1:
        notes.insert(0, f"{len(parts)} convex parts from {len(bodies)} bodies")
    parts, limit_notes = limit_parts(parts, params)
    method = "/".join(sorted(methods)) if methods else ("bodies" if len(bodies) > 1 else "hull")
    notes = list(dict.fromkeys(notes + list(limit_notes)))
    return ConvexResult(tuple(parts), method, tuple(notes), time.perf_counter() - t0)
