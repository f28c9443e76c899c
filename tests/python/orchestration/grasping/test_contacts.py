"""The contact checks give the same verdicts and values through the C++ core's passes as
through numpy's (:mod:`~grasp_pipeline.orchestration.grasping.pad_passes`)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from grasp_pipeline.orchestration.grasping import contacts, pad_passes
from grasp_pipeline.orchestration.grasping.candidates import Frames
from grasp_pipeline.orchestration.grasping.contacts import OK, ContactLimits
from grasp_pipeline.orchestration.grasping.hand_model import hand_model
from grasp_pipeline.orchestration.grasping.target_model import TargetModel

_LIMITS = ContactLimits(max_width_m=0.08, min_width_m=0.0, open_margin_m=0.01, max_opening_m=0.08,
                        palm_clearance_m=0.005, table_clearance_m=0.005, min_material_points=4,
                        contact_depth_m=0.004, min_contact_fraction=0.3, blocked_points=2)


def _box_target(rng, n: int) -> TargetModel:
    """A 4 x 3 x 6 cm box's surface points 10 cm above a table at z = 0, normals outward."""
    half = np.array([0.02, 0.015, 0.03])
    face = rng.integers(0, 6, n)
    p = rng.uniform(-1.0, 1.0, (n, 3)) * half
    axis, sign = face // 2, np.where(face % 2 == 0, 1.0, -1.0)
    p[np.arange(n), axis] = sign * half[axis]
    normals = np.zeros((n, 3))
    normals[np.arange(n), axis] = sign
    p = np.round(p / 0.002) * 0.002 + np.array([0.0, 0.0, 0.13])
    return TargetModel(p, np.ones(n, bool), normals, p.mean(axis=0), p[:, 2].copy())


def _frames(rng, pairs: int, lines: int) -> Frames:
    """Approaches from above (tilts up to 60 deg), ``lines`` closing lines per pair."""
    tilt = np.radians(rng.uniform(0.0, 60.0, pairs))
    az = rng.uniform(0.0, 2 * np.pi, pairs)
    a = np.column_stack([np.sin(tilt) * np.cos(az), np.sin(tilt) * np.sin(az), -np.cos(tilt)])
    c = np.cross(a, rng.normal(size=(pairs, 3)))
    c /= np.linalg.norm(c, axis=1, keepdims=True)
    b = np.cross(c, a)
    rep = np.repeat(np.arange(pairs), lines)
    x0 = np.tile(np.linspace(-0.01, 0.01, lines), pairs)
    return Frames(a[rep], c[rep], b[rep], x0, np.degrees(tilt)[rep], rep)


@pytest.mark.parametrize("seed, pairs, lines", [(0, 80, 5), (1, 3, 1), (2, 1, 3)])
@pytest.mark.parametrize("capped", [False, True])
def test_evaluate_is_the_same_through_the_core_and_numpy(monkeypatch, seed, pairs, lines, capped):
    rng = np.random.default_rng(seed)
    hand, target, frames = hand_model(0.04), _box_target(rng, 500), _frames(rng, pairs, lines)
    cap = rng.uniform(0.0, 0.02, len(frames)) if capped else None
    got = contacts.evaluate(frames, target, hand, _LIMITS, np.array([0.0, 0.0, 1.0]), 0.0, depth_cap=cap)
    monkeypatch.setattr(contacts, "passes_for", pad_passes.NumpyPasses)
    want = contacts.evaluate(frames, target, hand, _LIMITS, np.array([0.0, 0.0, 1.0]), 0.0, depth_cap=cap)
    for f in dataclasses.fields(want):
        g, w = getattr(got, f.name), getattr(want, f.name)
        assert g.dtype == w.dtype and np.array_equal(g, w, equal_nan=True), f.name
    if pairs * lines > 100:  # grasps pass, and refusals of several kinds occur
        assert np.any(want.code == OK) and len(np.unique(want.code)) >= 3
