"""Small synthetic scene clouds (world frame, table plane z = 0) for the point-check tests."""

import types

import numpy as np

from grasp_pipeline.orchestration.scene.scene_cloud import ENVIRONMENT, SceneCloud

STEP_M = 0.003
UP = np.array([0.0, 0.0, 1.0])


def block(x0, x1, y0, y1, z0, z1, step=STEP_M, sides=True):
    """Top face of an axis-aligned block and its -y side face (as an oblique camera sees it)."""
    xs, ys = np.arange(x0, x1 + 1e-9, step), np.arange(y0, y1 + 1e-9, step)
    X, Y = np.meshgrid(xs, ys)
    top = np.column_stack([X.ravel(), Y.ravel(), np.full(X.size, z1)])
    if not sides:
        return top
    Xs, Zs = np.meshgrid(xs, np.arange(z0, z1, step))
    return np.vstack([top, np.column_stack([Xs.ravel(), np.full(Xs.size, y0), Zs.ravel()])])


def table(x0=0.35, x1=0.75, y0=-0.15, y1=0.2, holes=(), step=STEP_M):
    """Table points (z = 0) with rectangular holes (x0, x1, y0, y1) where objects hide it."""
    X, Y = np.meshgrid(np.arange(x0, x1, step), np.arange(y0, y1, step))
    p = np.column_stack([X.ravel(), Y.ravel(), np.zeros(X.size)])
    for hx0, hx1, hy0, hy1 in holes:
        p = p[~((p[:, 0] > hx0) & (p[:, 0] < hx1) & (p[:, 1] > hy0) & (p[:, 1] < hy1))]
    return p


def scene(*parts, band_m=0.01) -> SceneCloud:
    """``parts``: (owner, points) pairs; owner ``ENVIRONMENT`` for the table."""
    pts = np.vstack([p for _, p in parts])
    own = np.concatenate([np.full(len(p), o, dtype=np.int64) for o, p in parts])
    return SceneCloud(pts, own, UP, 0.0, band_m)


def track_of(tid, pts, R=np.eye(3)):
    """A stand-in for a core track: the smoothed estimate's box around ``pts`` (axes ``R``)."""
    local = pts @ R
    lo, hi = local.min(axis=0), local.max(axis=0)
    c = R @ (0.5 * (lo + hi))
    top = float(pts[:, 2].max())
    c[2] = 0.5 * top
    ext = [hi[0] - lo[0], hi[1] - lo[1], top]
    e = types.SimpleNamespace(center=c, R_box=R, extents=ext, height_m=top, width_m=min(ext[:2]),
                              grasp_ok=False, resting=False, height_ok=True, width_ok=True,
                              notes=["floating/stacked: lowest point 30.0 mm above plane"])
    return types.SimpleNamespace(tid=tid, smoothed=e)


ENV = ENVIRONMENT
