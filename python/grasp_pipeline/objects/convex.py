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

An open or non-manifold single body (not watertight even after filling its small holes) is not
decomposed — CoACD would make thin shells of its surface, slowly — but collides as its convex
hull, with a warning saying so.

A cached decomposition is checked against its mesh when it is read: the file must be well formed
(arrays, counts, indices, finite vertices), written for this mesh (the key stored in it) and fit
it (the parts' bounding box within :data:`CACHE_BOUNDS_TOLERANCE` of the mesh's, their volume
within :data:`CACHE_VOLUME_FACTOR` of its, the mesh's vertices inside the parts). A file that fails is named in a warning and the
decomposition is computed again and rewritten.

Afterwards parts below ``min_part_volume_fraction`` of the total are dropped and the rest are
merged (the pair whose joint hull adds the least volume first) down to ``max_parts`` — every part
is a MuJoCo geom and costs collision time. Notes say how the parts were made; ``warnings`` (also
among the notes) say where the collision model is cruder than the mesh.
"""

from __future__ import annotations

import hashlib
import logging
import os
import tempfile
import threading
import time
import warnings
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Callable, Optional, Sequence

import numpy as np
import trimesh

from ..messages import brief
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
#: A cached decomposition's parts span the mesh's bounding box within this fraction of its
#: largest extent (CoACD's parts are hulls of pieces of the surface: on 14 household meshes they
#: were within 0.01 % of it, their volume within 1.00-1.08 times the mesh's, no vertex outside).
CACHE_BOUNDS_TOLERANCE = 0.02
#: ... and their total volume is within this factor of the mesh's volume, either way.
CACHE_VOLUME_FACTOR = 1.5
#: ... and at most this share of the mesh's vertices lie outside every part (by more than that
#: tolerance).
CACHE_MAX_OUTSIDE = 0.05
#: Largest cache file read [bytes] (32 parts of a few hundred vertices are about 100 kB).
MAX_CACHE_BYTES = 16_000_000

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
    ``"hull-no-coacd"``), notes for the user, the seconds it took, and the
    warnings among the notes (where the parts are cruder than the mesh, or the cache was bad)."""

    parts: tuple
    method: str
    notes: tuple[str, ...]
    seconds: float
    warnings: tuple[str, ...] = ()


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


def _pack(parts: Sequence[trimesh.Trimesh], key: str = "") -> dict:
    return {"vertices": np.concatenate([p.vertices for p in parts]).astype(np.float64),
            "faces": np.concatenate([p.faces for p in parts]).astype(np.int64),
            "n_vertices": np.array([len(p.vertices) for p in parts], dtype=np.int64),
            "n_faces": np.array([len(p.faces) for p in parts], dtype=np.int64),
            "key": np.array(key)}


def _array(arrays, name: str, kinds: str, ndim: int) -> np.ndarray:
    if name not in arrays:
        raise ValueError(f"no '{name}' array")
    a = np.asarray(arrays[name])
    if a.dtype.kind not in kinds or a.ndim != ndim or (ndim == 2 and a.shape[1] != 3):
        raise ValueError(f"'{name}' is {a.dtype} {a.shape}, not the expected layout")
    return a


def _unpack(arrays) -> tuple:
    """The parts stored in cache arrays; ValueError saying what is malformed."""
    v, f = _array(arrays, "vertices", "f", 2), _array(arrays, "faces", "iu", 2)
    nv, nf = _array(arrays, "n_vertices", "iu", 1), _array(arrays, "n_faces", "iu", 1)
    if len(nv) != len(nf) or not 1 <= len(nv) <= 10 * MAX_PARTS:
        raise ValueError(f"{len(nv)} vertex counts and {len(nf)} face counts")
    if (nv < 4).any() or (nf < 4).any() or nv.sum() != len(v) or nf.sum() != len(f):
        raise ValueError("the part sizes do not add up to the arrays")
    if not np.isfinite(v).all():
        raise ValueError("vertices that are not finite")
    v_end, f_end = np.cumsum(nv), np.cumsum(nf)
    parts = []
    for i in range(len(v_end)):
        v0, f0 = (v_end[i - 1], f_end[i - 1]) if i else (0, 0)
        faces = f[f0:f_end[i]]
        if faces.min() < 0 or faces.max() >= nv[i]:
            raise ValueError(f"part {i}: face indices outside its {nv[i]} vertices")
        parts.append(trimesh.Trimesh(v[v0:v_end[i]], faces, process=False))
    return tuple(parts)


def _misfit(parts: Sequence[trimesh.Trimesh], mesh: trimesh.Trimesh, stored_key: str, key: str) -> str:
    """Why cached ``parts`` are not a decomposition of ``mesh`` ("" when they fit)."""
    if stored_key and stored_key != key:
        return "it was written for another mesh"
    lo = np.min([p.bounds[0] for p in parts], axis=0)
    hi = np.max([p.bounds[1] for p in parts], axis=0)
    extent = float(np.max(mesh.extents))
    off = float(np.max(np.abs(np.concatenate([lo - mesh.bounds[0], hi - mesh.bounds[1]]))))
    if off > CACHE_BOUNDS_TOLERANCE * extent:
        return f"its parts' bounding box is {1e3 * off:.1f} mm off the mesh's ({1e3 * extent:.1f} mm wide)"
    volume, mesh_volume = sum(abs(p.volume) for p in parts), abs(mesh.volume)
    if mesh_volume > 0 and not mesh_volume / CACHE_VOLUME_FACTOR <= volume <= mesh_volume * CACHE_VOLUME_FACTOR:
        return f"its parts hold {volume / mesh_volume:.2f} times the mesh's volume"
    outside = _outside_share(parts, mesh.vertices, CACHE_BOUNDS_TOLERANCE * extent)
    if outside > CACHE_MAX_OUTSIDE:
        return f"{100 * outside:.0f} % of the mesh's vertices lie outside every part"
    return ""


def _outside_share(parts: Sequence[trimesh.Trimesh], vertices: np.ndarray, tol: float,
                   samples: int = 200) -> float:
    """Share of (up to ``samples``, evenly picked) ``vertices`` farther than ``tol`` outside every
    convex part (each part's face planes face outwards)."""
    pts = np.asarray(vertices, dtype=np.float64)[:: max(1, len(vertices) // samples)]
    inside = np.zeros(len(pts), dtype=bool)
    for p in parts:
        normals = np.asarray(p.face_normals)
        offsets = np.einsum("ij,ij->i", normals, np.asarray(p.triangles)[:, 0])
        inside |= (pts @ normals.T - offsets <= tol).all(axis=1)
    return float(1.0 - inside.mean()) if len(pts) else 0.0


def _read_cache(path: Path, mesh: trimesh.Trimesh, key: str) -> tuple[Optional[tuple], str]:
    """(the cached parts, "") when ``path`` holds a decomposition that fits ``mesh``; (None, "")
    when there is none; (None, a warning naming the file) when it is unusable."""
    if not path.is_file():
        return None, ""
    try:
        if path.stat().st_size > MAX_CACHE_BYTES:
            raise ValueError(f"{path.stat().st_size / 1e6:.0f} MB, more than a decomposition holds")
        with np.load(path, allow_pickle=False) as data:
            arrays = {k: data[k] for k in data.files}
        parts = _unpack(arrays)
        stored = str(arrays["key"]) if "key" in arrays and arrays["key"].dtype.kind == "U" else ""
        why = _misfit(parts, mesh, stored, key)
    except Exception as exc:  # a truncated or foreign file: recompute and overwrite it
        return None, f"convex cache {path} is unreadable or malformed ({brief(exc, 120)}); recomputed"
    if why:
        return None, f"convex cache {path} does not fit its mesh: {why}; recomputed"
    return parts, ""


def _write_cache(path: Path, parts: Sequence[trimesh.Trimesh], key: str = "") -> None:
    """Atomic write (temporary file + rename), so concurrent loaders never see half a file."""
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=".tmp-", suffix=".npz")
        with os.fdopen(fd, "wb") as fh:
            np.savez(fh, **_pack(parts, key))
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
    """CoACD's parts (their hulls). CoACD runs in a worker thread (it releases the GIL) while
    this thread waits in short steps, so Ctrl-C / SIGTERM end a decomposition of minutes at once
    (the thread is a daemon: it does not keep the process alive)."""
    coacd.set_log_level("error")
    out: dict = {}

    def work() -> None:
        try:
            out["pieces"] = coacd.run_coacd(
                coacd.Mesh(np.asarray(mesh.vertices, dtype=np.float64), np.asarray(mesh.faces, dtype=np.int32)),
                threshold=params.threshold, max_convex_hull=params.max_parts,
                preprocess_mode=params.preprocess_mode, preprocess_resolution=params.preprocess_resolution,
                resolution=params.resolution, mcts_nodes=params.mcts_nodes,
                mcts_iterations=params.mcts_iterations, mcts_max_depth=params.mcts_max_depth,
                seed=params.seed)
        except Exception as exc:  # handed to the caller
            out["error"] = exc

    worker = threading.Thread(target=work, name="coacd", daemon=True)
    worker.start()
    while worker.is_alive():
        worker.join(0.2)
    if "error" in out:
        raise out["error"]
    return [h for h in (hull_of(trimesh.Trimesh(v, f)) for v, f in out["pieces"]) if h is not None]


def decompose(mesh: trimesh.Trimesh, params: DecompositionParams = DecompositionParams(), *,
              cache_dir: Optional[os.PathLike] = None, source: str = "") -> ConvexResult:
    """Convex parts of one non-convex body: the cache (checked against ``mesh``), else CoACD
    (then cached), else its hull."""
    t0 = time.perf_counter()
    key = cache_key(mesh, params)
    path = _cache_path(cache_dir, key)
    cached, problem = _read_cache(path, mesh, key)
    if cached is not None:
        return ConvexResult(cached, "cache", (f"{len(cached)} convex parts (cached decomposition)",),
                            time.perf_counter() - t0)
    warned = ()
    if problem:
        log.warning("%s: %s", source or "mesh", problem)
        warned = (problem,)
    res = _computed(mesh, params, source, path, key)
    return ConvexResult(res.parts, res.method, warned + res.notes, time.perf_counter() - t0,
                        warned + res.warnings)


def _computed(mesh: trimesh.Trimesh, params: DecompositionParams, source: str, path: Path,
              key: str) -> ConvexResult:
    """CoACD's parts of ``mesh`` (written to the cache ``path``), else its hull."""
    coacd = _import_coacd()
    hull = hull_of(mesh)
    if coacd is None:
        parts = () if hull is None else (hull,)
        note = f"not convex, but coacd is not installed: one convex hull ({INSTALL_HINT})"
        return ConvexResult(parts, "hull-no-coacd", (note,), 0.0, (note,))
    try:
        pieces = _run_coacd(coacd, mesh, params)
    except Exception as exc:  # CoACD failing on a bad mesh must not lose the object
        log.warning("%s: coacd failed (%s); using the convex hull", source or "mesh", exc)
        pieces = []
    if not pieces:
        parts = () if hull is None else (hull,)
        note = "coacd gave no parts: one convex hull"
        return ConvexResult(parts, "hull", (note,), 0.0, (note,))
    parts, notes = limit_parts(pieces, params)
    parts = _unpack(_pack(parts))  # exactly what a cached load returns
    _write_cache(path, parts, key)
    return ConvexResult(parts, "coacd", (f"decomposed by coacd into {len(parts)} convex parts",) + notes, 0.0)


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


def _closed(body: trimesh.Trimesh) -> trimesh.Trimesh:
    """``body``, or a copy with its small holes filled when that closes it."""
    if body.is_watertight:
        return body
    filled = body.copy()
    trimesh.repair.fill_holes(filled)
    return filled if filled.is_watertight else body


def _body_parts(body: trimesh.Trimesh, params: DecompositionParams, decomp: Callable,
                alone: bool) -> tuple[list, list, list]:
    """Parts, notes and warnings of one body: its hull when convex, or when it is open (an open
    piece among several, or an open or non-manifold single body: not decomposed)."""
    if alone:
        body = _closed(body)
    hull = hull_of(body)
    if hull is None:
        return [], ["a flat body was skipped"], ["a flat body was skipped"]
    if is_convex_body(body, params.convex_volume_ratio, hull) or (not alone and not body.is_watertight):
        return [hull], [], []
    if not body.is_watertight:
        note = (f"open or non-manifold mesh ({_open_edges(body)} edges not shared by exactly two "
                "triangles): not decomposed, it collides as its convex hull; close the mesh for a "
                "tighter collision model")
        return [hull], [note], [note]
    res = decomp(body)
    return list(res.parts), list(res.notes), list(res.warnings)


def _open_edges(body: trimesh.Trimesh) -> int:
    """Edges not shared by exactly two faces (boundary or non-manifold edges)."""
    edges = np.sort(body.edges, axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    return int((counts != 2).sum())


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

    parts, notes, warns = [], [], []
    for body in bodies:
        p, n, w = _body_parts(body, params, decomp, alone=len(bodies) == 1)
        parts += p
        notes += n
        warns += w
    if not parts:
        raise MeshError(f"{source or 'mesh'}: no collision part with a positive volume "
                        "(the mesh is flat or degenerate)")
    if len(bodies) > 1:
        notes.insert(0, f"{len(parts)} convex parts from {len(bodies)} bodies")
    parts, limit_notes = limit_parts(parts, params)
    method = "/".join(sorted(methods)) if methods else ("bodies" if len(bodies) > 1 else "hull")
    notes = list(dict.fromkeys(notes + list(limit_notes)))
    return ConvexResult(tuple(parts), method, tuple(notes), time.perf_counter() - t0,
                        tuple(dict.fromkeys(warns)))
