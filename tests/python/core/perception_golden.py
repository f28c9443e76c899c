"""Golden digest of the per-frame perception path (`_core.Perception.process`).

The digest pins every per-frame output that the speed work on the perception core must
not change: the label of every input row (as a SHA-256 of the int32 labels plus the
per-label counts), all extracted planes and the locked table, every estimate (centre,
R_box, extents, theta, widths, height, anisotropy, PCA box, guards, notes), the view
quality, the track ids and every track's smoothed state after the frame.

The frame sequence is the benchmark's (``bench perception``: the four noise realisations
of the reference tabletop cycled, 30 Hz capture times), followed by frames from directly
above the blue cube, so that the NADIR path (quality rise, window restart, the second
estimate pass with the tracker's prior) is covered too.

Floats are stored with ``float.hex`` so that the comparison is exact. The golden file
``data/perception_golden.json`` was written by this module from the implementation
*before* the speed work (commit 458a09a):

    PYTHONPATH=python .venv/bin/python tests/python/core/perception_golden.py --write
"""

from __future__ import annotations

import argparse
import hashlib
import json
import sys
from pathlib import Path

import numpy as np

GOLDEN_PATH = Path(__file__).resolve().parent / "data" / "perception_golden.json"
BENCH_DISTINCT_FRAMES = 4   # noise realisations cycled by the benchmark
BENCH_SEQUENCE_FRAMES = 12  # > plane_lock_after, > tracker window
NADIR_SEQUENCE_FRAMES = 3   # frames from directly above the blue cube
FRAME_PERIOD_S = 1.0 / 30.0


def _hex(x) -> object:
    """Exact text of a float, a vector or a matrix (nested lists of float.hex)."""
    a = np.asarray(x, dtype=float)
    if a.ndim == 0:
        return float(a).hex()
    return [_hex(v) for v in a]


def _plane(p) -> dict | None:
    return None if p is None else {"n": _hex(p.n), "c": _hex(p.c)}


def _estimate(e) -> dict:
    return {
        "center": _hex(e.center), "R_box": _hex(e.R_box), "extents": _hex(e.extents),
        "theta_rad": _hex(e.theta_rad), "width_m": _hex(e.width_m),
        "perp_width_m": _hex(e.perp_width_m), "height_m": _hex(e.height_m),
        "anisotropy": _hex(e.anisotropy), "yaw_defined": bool(e.yaw_defined),
        "pca_center": _hex(e.pca.center), "pca_R": _hex(e.pca.R),
        "pca_extents": _hex(e.pca.extents), "pca_eigenvalues": _hex(e.pca.eigenvalues),
        "pca_tilt_deg": _hex(e.pca_tilt_deg), "lowest_m": _hex(e.lowest_m),
        "resting": bool(e.resting), "height_ok": bool(e.height_ok),
        "width_ok": bool(e.width_ok), "grasp_ok": bool(e.grasp_ok),
        "notes": list(e.notes), "undetermined_notes": list(e.undetermined_notes),
        "num_points": int(e.num_points),
    }


def frame_digest(fr, per) -> dict:
    """Everything one `PerceptionFrame` (and the tracker after it) produced, exactly."""
    f = fr.filter
    labels = np.asarray(f.labels, dtype=np.int32)
    values, counts = np.unique(labels, return_counts=True)
    return {
        "labels_sha256": hashlib.sha256(labels.tobytes()).hexdigest(),
        "label_counts": {str(int(v)): int(c) for v, c in zip(values, counts)},
        "table": _plane(f.table), "fit": _plane(f.fit), "table_index": int(f.table_index),
        "planes": [{"plane": _plane(c.plane), "count_whole": int(c.count_whole),
                    "subsample_inliers": int(c.subsample_inliers),
                    "subsample_size": int(c.subsample_size), "removed": int(c.removed),
                    "refined": bool(c.refined)} for c in f.planes],
        "decision": str(f.decision), "num_valid": int(f.num_valid),
        "num_candidates": int(f.num_candidates), "cluster_ids": list(f.cluster_ids),
        "estimate_labels": list(fr.estimate_labels), "tids": list(fr.tids),
        "failed_labels": list(fr.failed_labels), "failures": list(fr.failures),
        "estimates": [_estimate(e) for e in fr.estimates],
        "views": [{"quality": str(v.quality), "angle_deg": _hex(v.angle_deg)} for v in fr.views],
        "tracks": [{"tid": int(t.tid), "quality": str(t.quality),
                    "last_seen_s": _hex(t.last_seen_s), "smoothed": _estimate(t.smoothed)}
                   for t in per.tracker.tracks],
    }


def frame_sequence() -> list[tuple[np.ndarray, np.ndarray]]:
    """(points, camera position) of every frame of the golden session, in order."""
    from grasp_pipeline.perception import synthetic as syn

    bench = [syn.tabletop_frame(seed=s) for s in range(BENCH_DISTINCT_FRAMES)]
    frames = [(bench[i % BENCH_DISTINCT_FRAMES][0], bench[i % BENCH_DISTINCT_FRAMES][1][:3, 3])
              for i in range(BENCH_SEQUENCE_FRAMES)]
    T = syn.look_at(np.array([0.56, -0.03, 0.59]), np.array([0.56, -0.03, 0.2]))
    for s in range(NADIR_SEQUENCE_FRAMES):
        pts, _ = syn.render_depth(syn.reference_tabletop(), T, rng=np.random.default_rng(100 + s))
        frames.append((pts, T[:3, 3]))
    return frames


def session_digest() -> list[dict]:
    """Run the golden session with default parameters; one digest per frame."""
    from grasp_pipeline import _core

    per = _core.Perception(_core.SceneFilterParams(), _core.ObbParams())
    out = []
    for i, (pts, cam) in enumerate(frame_sequence()):
        fr = per.process(pts, cam, i * FRAME_PERIOD_S)
        out.append(frame_digest(fr, per))
    return out


def _float_leaves(a, b, path=""):
    """(path, |difference|) of every float.hex leaf that differs between a and b."""
    if isinstance(a, dict):
        for k in a:
            yield from _float_leaves(a[k], b.get(k) if isinstance(b, dict) else None, f"{path}.{k}")
    elif isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        for i, (x, y) in enumerate(zip(a, b)):
            yield from _float_leaves(x, y, f"{path}[{i}]")
    elif isinstance(a, str) and isinstance(b, str) and a != b and a.startswith(("0x", "-0x")):
        try:
            yield path, abs(float.fromhex(a) - float.fromhex(b))
        except ValueError:
            pass


#: Floats may differ by this much relative to their size: glibc picks its libm routines
#: (FMA variants) and the core its target_clones by the CPU, so machines with and without
#: FMA/AVX2 round the last bits differently, and the PCA axes of a nearly flat NADIR view
#: (tilt 0.1 deg, an ill-conditioned eigenproblem) amplify that to ~2e-10 relative (measured
#: on an AMD EPYC with FMA/AVX2 against the golden file). Integers, labels (their SHA-256),
#: counts, ids, qualities and notes must match exactly; any change of the algorithm moves
#: the floats by far more than this.
FLOAT_REL_TOL = 1e-9


def _is_hex_float(x) -> bool:
    return isinstance(x, str) and x.startswith(("0x", "-0x"))


def matches(golden, now) -> bool:
    """Whether ``now`` equals ``golden``, floats within :data:`FLOAT_REL_TOL`."""
    if isinstance(golden, dict):
        return isinstance(now, dict) and golden.keys() == now.keys() and \
            all(matches(golden[k], now[k]) for k in golden)
    if isinstance(golden, list):
        return isinstance(now, list) and len(golden) == len(now) and \
            all(matches(g, n) for g, n in zip(golden, now))
    if _is_hex_float(golden) and _is_hex_float(now):
        a, b = float.fromhex(golden), float.fromhex(now)
        return abs(a - b) <= FLOAT_REL_TOL * max(1.0, abs(a), abs(b))
    return golden == now


def describe_differences(golden: list[dict], now: list[dict], limit: int = 20) -> list[str]:
    """Human-readable first differences (float leaves with the size of the difference)."""
    lines = []
    for i, (g, n) in enumerate(zip(golden, now)):
        if g == n:
            continue
        for path, d in _float_leaves(g, n):
            lines.append(f"frame {i}{path}: |diff| = {d:.3g}")
        for k in g:
            if g[k] != n.get(k) and not any(line.startswith(f"frame {i}.{k}") for line in lines):
                lines.append(f"frame {i}.{k}: {str(g[k])[:120]} != {str(n.get(k))[:120]}")
    if len(golden) != len(now):
        lines.append(f"{len(golden)} golden frames, {len(now)} now")
    return lines[:limit]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="(re)write the golden file")
    args = ap.parse_args(argv)
    digest = session_digest()
    if args.write:
        GOLDEN_PATH.parent.mkdir(parents=True, exist_ok=True)
        GOLDEN_PATH.write_text(json.dumps(digest, indent=0, sort_keys=True) + "\n")
        print(f"wrote {GOLDEN_PATH} ({len(digest)} frames)")
        return 0
    golden = json.loads(GOLDEN_PATH.read_text())
    diffs = describe_differences(golden, digest)
    print("identical" if not diffs else "\n".join(diffs))
    return 0 if not diffs else 1


if __name__ == "__main__":
    sys.exit(main())
