"""The contact checks' shared products equal the plain per-frame computations, bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from grasp_pipeline.motion.thin_matmul import thin_matmul
from grasp_pipeline.orchestration.grasping import contacts
from grasp_pipeline.orchestration.grasping.candidates import Frames
from grasp_pipeline.orchestration.grasping.contacts import ContactLimits
from grasp_pipeline.orchestration.grasping.hand_model import hand_model


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
    got = contacts._normals_along_closing(normals, frames)
    assert got.dtype == np.float32 and got.flags["C_CONTIGUOUS"]
    assert np.array_equal(got, thin_matmul(normals, np.ascontiguousarray(frames.c.T)).astype(np.float32))


def test_normals_along_closing_with_a_pair_of_several_closing_axes():
    rng = np.random.default_rng(5)
    frames = _frames(rng, 4, 3)
    c = frames.c.copy()
    c[1] = _unit(np.cross(frames.a[1], [0.3, 0.2, 0.9]))  # not its pair's first axis
    frames = Frames(frames.a, c, np.cross(c, frames.a), frames.x0, frames.tilt_deg, frames.pair)
    normals = _unit(rng.normal(size=(50, 3)))
    assert np.array_equal(contacts._normals_along_closing(normals, frames),
                          thin_matmul(normals, np.ascontiguousarray(frames.c.T)).astype(np.float32))


def test_projection_is_the_product_of_each_pairs_axes():
    """The projection is the fixed-order product of the points and the pairs' axes, spread to
    the frames of each pair."""
    rng = np.random.default_rng(6)
    for pairs, n in ((30, 300), (345, 536), (2, 1)):
        frames = _frames(rng, pairs, 4)
        pts = rng.normal(0.0, 0.05, size=(n, 3))
        X, Y, Z = contacts._project(pts, frames)
        uniq, first = np.unique(frames.pair, return_index=True)
        axes = np.concatenate([frames.b[first], frames.c[first], frames.a[first]]).T.astype(np.float32)
        proj = thin_matmul(pts.astype(np.float32), np.ascontiguousarray(axes))
        col = np.searchsorted(uniq, frames.pair)
        for got, k in ((X, 0), (Y, 1), (Z, 2)):
            assert np.array_equal(got, proj[:, k * len(uniq) + col])


def _blocked_reference(X, Y, Z, x0, y_mid, z_tcp, opening, lim, hand):
    """The fingers' sweep counted finger by finger (the plain form of the check)."""
    tol = lim.tolerance_m
    lateral = np.abs(X - x0[None, :]) <= hand.pad_half_width_m + tol
    ahead = Z <= (z_tcp + hand.pad_half_length_m)[None, :]
    inner = 0.5 * opening[None, :] - tol
    outer = 0.5 * opening[None, :] + hand.finger_thickness_m
    worst = np.zeros(X.shape[1], dtype=np.int64)
    for s in (1.0, -1.0):
        d = s * (Y - y_mid[None, :])
        worst = np.maximum(worst, (lateral & ahead & (d >= inner) & (d <= outer)).sum(axis=0))
    return worst


#: Contact limits of the bit-for-bit comparisons below.
_LIMITS = ContactLimits(max_width_m=0.08, min_width_m=0.0, open_margin_m=0.01, max_opening_m=0.08,
                        palm_clearance_m=0.005, table_clearance_m=0.005, min_material_points=4,
                        contact_depth_m=0.004, min_contact_fraction=0.3, blocked_points=2)


def _grid_case(seed: int, n_frames: int, n_points: int):
    """(rng, frames, X, Y, Z): random frames and points on a 2 mm grid (so that many lie
    exactly on the pads' and fingers' faces), projected into the frames."""
    rng = np.random.default_rng(seed)
    frames = _frames(rng, n_frames, 5)
    pts = np.round(rng.normal(0.0, 0.03, size=(n_points, 3)) / 0.002) * 0.002
    return (rng, frames, *contacts._project(pts, frames))


def test_fingers_blocked_equals_the_finger_by_finger_count():
    hand, lim = hand_model(0.04), _LIMITS
    rng, frames, X, Y, Z = _grid_case(7, 60, 700)
    y_mid = np.round(rng.normal(0.0, 0.01, len(frames)) / 0.002) * 0.002
    z_tcp = rng.normal(0.0, 0.01, len(frames))
    opening = np.round(rng.uniform(0.0, 0.08, len(frames)) / 0.002) * 0.002
    got = contacts._fingers_blocked(np.abs(X - frames.x0[None, :]), Y, Z, y_mid, z_tcp, opening, lim, hand)
    want = _blocked_reference(X, Y, Z, frames.x0, y_mid, z_tcp, opening, lim, hand)
    assert got.dtype == want.dtype and np.array_equal(got, want) and want.max() > 0


def test_coverage_equals_the_signed_form():
    """The contact patch near each pad edge: ``sign · (Y − edge) >= −depth`` as the check reads."""
    hand, lim = hand_model(0.04), _LIMITS
    rng, frames, X, Y, _ = _grid_case(8, 40, 500)
    mat = rng.random(X.shape) < 0.6
    for sign in (1.0, -1.0):
        edge = np.round(rng.normal(0.0, 0.02, len(frames)) / 0.002) * 0.002
        cov, near = contacts._coverage(X, Y, mat, edge, sign, lim, hand)
        want = mat & (sign * (Y - edge[None, :]) >= -lim.contact_depth_m)
        assert np.array_equal(near, want) and 0 < want.sum() < want.size
        span = np.max(X, axis=0, where=want, initial=-np.inf) - np.min(X, axis=0, where=want, initial=np.inf)
        width = np.clip(np.nan_to_num(span, neginf=0.0, posinf=0.0) / (2.0 * hand.pad_half_width_m), 0.0, 1.0)
        assert np.array_equal(cov, width)

