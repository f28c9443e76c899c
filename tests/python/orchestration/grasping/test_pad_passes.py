"""The contact checks' passes over the object's points: the shared products equal the plain
per-frame computations, and the C++ core's passes equal numpy's, bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from grasp_pipeline import _core
from grasp_pipeline.motion.thin_matmul import thin_matmul
from grasp_pipeline.orchestration.grasping import pad_passes
from grasp_pipeline.orchestration.grasping.candidates import Frames
from grasp_pipeline.orchestration.grasping.hand_model import hand_model
from grasp_pipeline.orchestration.grasping.pad_passes import CorePasses, EndLimits, NumpyPasses
from grasp_pipeline.orchestration.grasping.target_model import TargetModel


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _frames(rng, pairs: int, lines: int) -> Frames:
    """Frames of ``pairs`` random (approach, closing) pairs, ``lines`` lines each."""
    a = _unit(rng.normal(size=(pairs, 3)))
    c = _unit(np.cross(a, rng.normal(size=(pairs, 3))))
    b = np.cross(c, a)
    rep = np.repeat(np.arange(pairs), lines)
    x0 = rng.normal(0.0, 0.02, len(rep))
    return Frames(a[rep], c[rep], b[rep], x0, np.zeros(len(rep)), rep)


@pytest.mark.parametrize("n, pairs, lines", [(1, 1, 1), (7, 3, 5), (536, 345, 3), (900, 40, 7)])
def test_normals_along_closing_equal_the_full_product(n, pairs, lines):
    rng = np.random.default_rng(n + pairs)
    frames = _frames(rng, pairs, lines)
    normals = _unit(rng.normal(size=(n, 3)))
    got = pad_passes.normals_along_closing(normals, frames)
    assert got.dtype == np.float32 and got.flags["C_CONTIGUOUS"]
    assert np.array_equal(got, thin_matmul(normals, np.ascontiguousarray(frames.c.T)).astype(np.float32))


def test_normals_along_closing_with_a_pair_of_several_closing_axes():
    rng = np.random.default_rng(5)
    frames = _frames(rng, 4, 3)
    c = frames.c.copy()
    c[1] = _unit(np.cross(frames.a[1], [0.3, 0.2, 0.9]))  # not its pair's first axis
    frames = Frames(frames.a, c, np.cross(c, frames.a), frames.x0, frames.tilt_deg, frames.pair)
    normals = _unit(rng.normal(size=(50, 3)))
    assert np.array_equal(pad_passes.normals_along_closing(normals, frames),
                          thin_matmul(normals, np.ascontiguousarray(frames.c.T)).astype(np.float32))


def test_projection_is_the_product_of_each_pairs_axes():
    """The projection is the fixed-order product of the points and the pairs' axes, spread to
    the frames of each pair."""
    rng = np.random.default_rng(6)
    for pairs, n in ((30, 300), (345, 536), (2, 1)):
        frames = _frames(rng, pairs, 4)
        pts = rng.normal(0.0, 0.05, size=(n, 3))
        X, Y, Z = pad_passes.project(pts, frames)
        uniq, first = np.unique(frames.pair, return_index=True)
        axes = np.concatenate([frames.b[first], frames.c[first], frames.a[first]]).T.astype(np.float32)
        proj = thin_matmul(pts.astype(np.float32), np.ascontiguousarray(axes))
        col = np.searchsorted(uniq, frames.pair)
        for got, k in ((X, 0), (Y, 1), (Z, 2)):
            assert np.array_equal(got, proj[:, k * len(uniq) + col])


def _blocked_reference(X, Y, Z, x0, y_mid, z_tcp, opening, tol, hand):
    """The fingers' sweep counted finger by finger (the plain form of the check)."""
    lateral = np.abs(X - x0[None, :]) <= hand.pad_half_width_m + tol
    ahead = Z <= (z_tcp + hand.pad_half_length_m)[None, :]
    inner = 0.5 * opening[None, :] - tol
    outer = 0.5 * opening[None, :] + hand.finger_thickness_m
    worst = []
    for s in (1.0, -1.0):
        d = s * (Y - y_mid[None, :])
        worst.append((lateral & ahead & (d >= inner) & (d <= outer)).sum(axis=0))
    return worst


def _grid_case(seed: int, n_frames: int, n_points: int, lines: int = 5):
    """(rng, frames, points): random frames and points on a 2 mm grid (so that many lie
    exactly on the pads' and fingers' faces)."""
    rng = np.random.default_rng(seed)
    frames = _frames(rng, n_frames, lines)
    pts = np.round(rng.normal(0.0, 0.03, size=(n_points, 3)) / 0.002) * 0.002
    return rng, frames, pts


def test_fingers_blocked_equals_the_finger_by_finger_count():
    hand, tol = hand_model(0.04), 0.002
    rng, frames, pts = _grid_case(7, 60, 700)
    X, Y, Z = pad_passes.project(pts, frames)
    y_mid = (np.round(rng.normal(0.0, 0.01, len(frames)) / 0.002) * 0.002).astype(np.float32)
    z_tcp = rng.normal(0.0, 0.01, len(frames))
    opening = (np.round(rng.uniform(0.0, 0.08, len(frames)) / 0.002) * 0.002).astype(np.float32)
    got = pad_passes.fingers_blocked(np.abs(X - frames.x0[None, :]), Y, Z, y_mid, z_tcp + hand.pad_half_length_m,
                                     0.5 * opening - tol, 0.5 * opening + hand.finger_thickness_m,
                                     hand.pad_half_width_m + tol)
    want = _blocked_reference(X, Y, Z, frames.x0, y_mid, z_tcp, opening, tol, hand)
    for g, w in zip(got, want):
        assert g.dtype == np.int64 and np.array_equal(g, w) and w.max() > 0


def test_patch_near_equals_the_signed_form():
    """The contact patch near each pad edge: ``sign · (Y − edge) >= −depth`` as the check reads."""
    rng, frames, pts = _grid_case(8, 40, 500)
    _, Y, _ = pad_passes.project(pts, frames)
    mat = rng.random(Y.shape) < 0.6
    for sign in (1.0, -1.0):
        edge = (np.round(rng.normal(0.0, 0.02, len(frames)) / 0.002) * 0.002).astype(np.float32)
        want = mat & (sign * (Y - edge[None, :]) >= -0.004)
        got = pad_passes.patch_near(Y, mat, edge, sign, 0.004)
        assert np.array_equal(got, want) and 0 < want.sum() < want.size


def _target(rng, pts: np.ndarray) -> TargetModel:
    normals = _unit(rng.normal(size=pts.shape))
    centroid = pts.mean(axis=0) if len(pts) else np.zeros(3)
    return TargetModel(pts, np.ones(len(pts), bool), normals, centroid, pts[:, 2].copy())


def _inputs(rng, passes, hand):
    """Depths (float32 and float64), the material's ends and the fingers' bands for the
    passes' frames: values of the checks, on the 2 mm grid where a tie is likely."""
    k = len(passes.frames)
    z32 = (np.round(rng.normal(0.0, 0.02, k) / 0.002) * 0.002).astype(np.float32)
    z64 = np.round(rng.normal(0.0, 0.02, k) / 0.002) * 0.002
    y_lo, y_hi, count = NumpyPasses(passes.target, passes.frames, hand).material(z64)
    y_mid = np.where(count > 0, 0.5 * (np.where(count > 0, y_lo, 0.0) + np.where(count > 0, y_hi, 0.0)), 0.0)
    opening = np.minimum(np.nan_to_num(y_hi - y_lo, posinf=0.0, neginf=0.0) + 0.01, 0.08)
    return z32, z64, y_lo, y_hi, y_mid, 0.5 * opening - 0.002, 0.5 * opening + hand.finger_thickness_m


@pytest.mark.parametrize("seed, pairs, lines, n", [(1, 2, 1, 1), (2, 1, 2, 40), (3, 30, 5, 600),
                                                    (4, 200, 3, 250), (5, 7, 9, 3)])
def test_core_passes_equal_numpy_passes(seed, pairs, lines, n):
    hand = hand_model(0.04)
    rng, frames, pts = _grid_case(seed, pairs, n, lines)
    target = _target(rng, pts)
    core, ref = CorePasses(target, frames, hand), NumpyPasses(target, frames, hand)
    for got, want in zip(core.depth_bounds(), ref.depth_bounds()):
        assert got.dtype == want.dtype and np.array_equal(got, want)
    z32, z64, y_lo, y_hi, y_mid, inner, outer = _inputs(rng, core, hand)
    assert y_mid.dtype == inner.dtype == np.float32
    for z in (z32, z64):
        for got, want in zip(core.material(z), ref.material(z)):
            assert got.dtype == want.dtype and np.array_equal(got, want)
    lim = EndLimits(0.004, float(np.cos(np.radians(35.0))), hand.pad_half_width_m + 0.002)
    got, want = (p.ends(lim, z64, y_lo, y_hi, y_mid, inner, outer) for p in (core, ref))
    for side in ("upper", "lower"):
        for name in ("x_lo", "x_hi", "normal_sum", "count", "facing"):
            g, w = getattr(getattr(got, side), name), getattr(getattr(want, side), name)
            assert g.dtype == w.dtype and np.array_equal(g, w), (side, name)
    assert np.array_equal(got.blocked_upper, want.blocked_upper)
    assert np.array_equal(got.blocked_lower, want.blocked_lower)
    if n >= 200:  # the cases are not empty: material, patches and blocked fingers occur
        assert got.upper.count.max() > 0 and got.lower.facing.max() > 0 and got.blocked_upper.max() > 0


def test_a_single_frame_takes_numpys_passes():
    """numpy sums a single frame's column pairwise: that frame goes through numpy's passes."""
    hand = hand_model(0.04)
    rng, frames, pts = _grid_case(9, 1, 50, 1)
    assert isinstance(pad_passes.passes_for(_target(rng, pts), frames, hand), NumpyPasses)
    rng, frames, pts = _grid_case(9, 1, 50, 2)
    assert isinstance(pad_passes.passes_for(_target(rng, pts), frames, hand), CorePasses)
    assert isinstance(pad_passes.passes_for(_target(rng, pts[:0]), frames, hand), NumpyPasses)


def test_core_passes_reject_bad_arrays():
    xyz = np.zeros((3, 2, 5), np.float32)
    col, x0 = np.array([0, 1], np.int64), np.zeros(2)
    with pytest.raises(ValueError, match="column: frame 1 reads column 2 of 2"):
        _core.pad_depth_bounds(xyz, np.array([0, 2], np.int64), x0, 0.01, 0.03)
    with pytest.raises(TypeError, match="xyz: expected dtype float32"):
        _core.pad_depth_bounds(xyz.astype(float), col, x0, 0.01, 0.03)
    with pytest.raises(ValueError, match="x0: expected shape"):
        _core.pad_material(xyz, col, np.zeros(3), 0.01, np.zeros(2), 0.01)
    with pytest.raises(TypeError, match="z_tcp: expected dtype float64"):
        _core.pad_contact_ends(xyz, col, x0, np.zeros((1, 5), np.float32), np.zeros(2, np.int64),
                               np.zeros(2, np.int32), *(np.zeros(2, np.float32),) * 5, 0.01, 0.01, 0.004, 0.8, 0.012)
