"""RViz-like PNG snapshots of one perception frame.

The view users know from the original RViz setup: object points red, environment points
blue, each object's box as a green wireframe, each grasp's approach as an orange arrow,
optionally the table plane as a light grid — drawn with matplotlib's 3-D axes on the Agg
backend (no display needed, no pyplot global state: each call builds its own Figure).

Choices (ours):
- Equal aspect: the box aspect is set to the data ranges, so a cube looks like a cube.
- Limits: the objects, boxes and grasps plus ``max(12 cm, half their horizontal span)`` of
  context around them (environment points outside are not drawn, so a far wall or the floor
  cannot shrink the objects to dots); without objects, the environment's 1st–99th percentiles.
- Speed: at most ``max_environment_points`` (20 000) environment and ``max_object_points``
  (20 000) object points are drawn, picked with a fixed stride (deterministic); at most
  ``MAX_TICK_INTERVALS`` tick intervals per axis (steps of 1, 2 or 5 x 10^k: each tick is a
  set of artists made at every draw) and a fast PNG compression level. A 307 k-point frame
  renders in about 0.1 s once matplotlib is imported.
- Viewpoint: ``elev=35°``, ``azim=-150°`` — obliquely from behind-left of the robot base (world
  x forward, z up), like RViz's default orbit camera; both are arguments.
- ``plane`` may be a ``_core.Plane`` (has ``n`` and ``c``) or an ``(n, c)`` pair.
"""

from __future__ import annotations

import os
from typing import Iterable, Sequence

import numpy as np

OBJECT_RGB = (1.0, 0.0, 0.0)       # red
ENVIRONMENT_RGB = (0.1, 0.3, 1.0)  # blue
BOX_RGB = (0.0, 0.85, 0.0)         # green
ARROW_RGB = (1.0, 0.55, 0.0)       # orange
PLANE_RGB = (0.6, 0.6, 0.6)

#: zlib level of the PNG files: 1 encodes a snapshot about twice as fast as the default 6
#: (~16 ms instead of ~33 ms for 960x720), for a file a few per cent larger.
PNG_COMPRESS_LEVEL = 1
#: At most this many intervals between the tick labels of an axis (matplotlib's default
#: locator puts up to 9 on a 3-D axis; each tick is a set of artists made at every draw).
MAX_TICK_INTERVALS = 6

# Unit-cube corners (±1/2) and the 12 edges between them.
_CORNERS = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)])
_EDGES = [(i, j) for i in range(8) for j in range(i + 1, 8)
          if np.count_nonzero(_CORNERS[i] != _CORNERS[j]) == 1]


def _finite_rows(points) -> np.ndarray:
    """The finite rows of an (N, 3) array as float64 (selected before the conversion: a
    frame's cloud is float32 and mostly NaN-free)."""
    if points is None:
        return np.zeros((0, 3))
    p = np.asarray(points).reshape(-1, 3)
    return p[np.isfinite(p).all(axis=1)].astype(float)


def _subsample(points: np.ndarray, limit: int) -> np.ndarray:
    if limit <= 0 or len(points) <= limit:
        return points
    idx = np.linspace(0, len(points) - 1, limit).astype(np.int64)
    return points[idx]


def box_corners(center, R, extents) -> np.ndarray:
    """(8, 3) corners of an oriented box (columns of R = box axes, extents = full sizes)."""
    return np.asarray(center, float) + (_CORNERS * np.asarray(extents, float)) @ np.asarray(R, float).T


def _plane_nc(plane) -> tuple[np.ndarray, float] | None:
    if plane is None:
        return None
    if hasattr(plane, "n") and hasattr(plane, "c"):
        n, c = plane.n, plane.c
    else:
        n, c = plane
    n = np.asarray(n, float).reshape(3)
    return n, float(c)


def _limits(focus: np.ndarray, env: np.ndarray, context_m: float = 0.12, margin: float = 0.03):
    """View box: the focus (objects, boxes, arrows) plus some context, else the environment."""
    if len(focus):
        lo, hi = focus.min(axis=0), focus.max(axis=0)
        ctx = max(context_m, 0.5 * float(np.max(hi[:2] - lo[:2])))
        lo = lo - np.array([ctx, ctx, margin])
        hi = hi + np.array([ctx, ctx, margin])
        if len(env):  # show the surface the objects stand on, not the floor far below
            lo[2] = min(lo[2], max(float(np.percentile(env[:, 2], 1.0)), lo[2] - 0.1))
    elif len(env):
        lo, hi = np.percentile(env, [1.0, 99.0], axis=0)
        lo, hi = lo - margin, hi + margin
    else:
        return np.array([-0.5, -0.5, -0.5]), np.array([0.5, 0.5, 0.5])
    span = np.maximum(hi - lo, 1e-3)
    return lo, lo + span


def _unit(a: np.ndarray) -> np.ndarray:
    return a / max(np.linalg.norm(a), 1e-12)


def _focus_points(obj: np.ndarray, boxes: list, grasps: list, arrow_length_m: float) -> np.ndarray:
    """What the view must show: object points, box corners and both ends of each grasp arrow."""
    focus = [obj] if len(obj) else []
    focus += [box_corners(*b) for b in boxes]
    for p, a in grasps:
        a = _unit(a)
        focus.append(np.vstack([p, p - a * arrow_length_m]))
    return np.vstack(focus) if focus else np.zeros((0, 3))


def _new_axes(size_px: tuple[int, int]):
    """A white Agg-backed Figure of ``size_px`` pixels and its 3-D axes."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from mpl_toolkits.mplot3d import Axes3D  # noqa: F401  (registers the 3-D projection)

    dpi = 100
    fig = Figure(figsize=(size_px[0] / dpi, size_px[1] / dpi), dpi=dpi, facecolor="white")
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(projection="3d")
    ax.set_facecolor("white")
    return fig, ax


def _draw_points(ax, env: np.ndarray, obj: np.ndarray, max_environment_points: int,
                 max_object_points: int) -> None:
    """Environment points (blue), then object points (red), each subsampled to its limit."""
    env_draw = _subsample(env, max_environment_points)
    if len(env_draw):
        ax.scatter(env_draw[:, 0], env_draw[:, 1], env_draw[:, 2], s=2.0, c=[ENVIRONMENT_RGB],
                   marker=".", linewidths=0, depthshade=False, rasterized=True)
    obj_draw = _subsample(obj, max_object_points)
    if len(obj_draw):
        ax.scatter(obj_draw[:, 0], obj_draw[:, 1], obj_draw[:, 2], s=3.0, c=[OBJECT_RGB],
                   marker=".", linewidths=0, depthshade=False, rasterized=True)


def _draw_plane(ax, plane, lo: np.ndarray, hi: np.ndarray) -> None:
    """The plane as a 7×7 wireframe over the view's x/y range (skipped when vertical)."""
    nc = _plane_nc(plane)
    if nc is not None and abs(nc[0][2]) > 1e-6:
        n, c = nc
        xs = np.linspace(lo[0], hi[0], 7)
        ys = np.linspace(lo[1], hi[1], 7)
        X, Y = np.meshgrid(xs, ys)
        Z = -(c + n[0] * X + n[1] * Y) / n[2]
        ax.plot_wireframe(X, Y, Z, color=PLANE_RGB, linewidth=0.5, alpha=0.6)


def _draw_boxes(ax, boxes: list) -> None:
    """Box wireframes (green), each labelled ``#i`` just above its top face."""
    from mpl_toolkits.mplot3d.art3d import Line3DCollection

    segs = []
    for b in boxes:
        k = box_corners(*b)
        segs += [(k[i], k[j]) for i, j in _EDGES]
    ax.add_collection3d(Line3DCollection(segs, colors=[BOX_RGB], linewidths=1.6))
    for i, (c, R, e) in enumerate(boxes):
        top = c + R[:, 2] * (e[2] / 2.0 + 0.01)
        ax.text(top[0], top[1], top[2], f"#{i}", color="black", fontsize=8)


def _draw_grasps(ax, grasps: list, arrow_length_m: float) -> None:
    """One orange arrow per grasp, ending at the grasp position along its approach."""
    for p, a in grasps:
        a = _unit(a)
        start = p - a * arrow_length_m
        ax.quiver(start[0], start[1], start[2], a[0], a[1], a[2], length=arrow_length_m,
                  color=ARROW_RGB, linewidth=2.2, arrow_length_ratio=0.3, normalize=False)


def _set_view(ax, lo: np.ndarray, hi: np.ndarray, elev: float, azim: float) -> None:
    """Limits, equal aspect, viewpoint and axis labels."""
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect(tuple(hi - lo))
    ax.view_init(elev=elev, azim=azim)
    ax.set_xlabel("x [m]", fontsize=8)
    ax.set_ylabel("y [m]", fontsize=8)
    ax.set_zlabel("z [m]", fontsize=8)
    ax.tick_params(labelsize=7)
    from matplotlib.ticker import MaxNLocator

    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.set_major_locator(MaxNLocator(nbins=MAX_TICK_INTERVALS, steps=[1, 2, 5, 10]))


def build_figure(object_points=None, object_labels=None, environment_points=None,
                 boxes: Iterable = (), grasps: Iterable = (), plane=None, title: str = "",
                 *, elev: float = 35.0, azim: float = -150.0, size_px: tuple[int, int] = (960, 720),
                 max_environment_points: int = 20000, max_object_points: int = 20000,
                 arrow_length_m: float = 0.08):
    """The matplotlib Figure of a snapshot (see :func:`render_snapshot`)."""
    obj = _finite_rows(object_points)
    env = _finite_rows(environment_points)
    labels = None if object_labels is None else np.asarray(object_labels).reshape(-1)
    boxes = [(np.asarray(c, float), np.asarray(R, float), np.asarray(e, float)) for c, R, e in boxes]
    grasps = [(np.asarray(p, float), np.asarray(a, float)) for p, a in grasps]

    fig, ax = _new_axes(size_px)
    lo, hi = _limits(_focus_points(obj, boxes, grasps, arrow_length_m), env)
    n_env_total = len(env)
    # Environment points outside the view would only be clipped by hand; drop them here.
    if len(env):
        env = env[((env >= lo) & (env <= hi)).all(axis=1)]

    _draw_points(ax, env, obj, max_environment_points, max_object_points)
    _draw_plane(ax, plane, lo, hi)
    if boxes:
        _draw_boxes(ax, boxes)
    _draw_grasps(ax, grasps, arrow_length_m)
    _set_view(ax, lo, hi, elev, azim)

    n_obj = len(np.unique(labels[labels >= 0])) if labels is not None and len(labels) else 0
    subtitle = (f"{len(obj)} object points ({n_obj} groups), {n_env_total} environment points, "
                f"{len(boxes)} boxes, {len(grasps)} grasps")
    fig.suptitle((title + "\n" if title else "") + subtitle, fontsize=9)
    fig.subplots_adjust(left=0.0, right=1.0, bottom=0.02, top=0.92)
    return fig


def snapshot_image(*args, **kwargs) -> np.ndarray:
    """The snapshot as an (H, W, 3) uint8 RGB image (for videos); arguments as build_figure."""
    fig = build_figure(*args, **kwargs)
    fig.canvas.draw()
    return np.asarray(fig.canvas.buffer_rgba())[..., :3].copy()


def render_snapshot(path: str | os.PathLike, object_points=None, object_labels=None,
                    environment_points=None, boxes: Sequence = (), grasps: Sequence = (),
                    plane=None, title: str = "", **kwargs) -> str:
    """Write an RViz-like PNG of one frame and return its path.

    ``boxes``: ``(center (3,), R (3, 3) with the box axes as columns, extents (3,))`` each;
    ``grasps``: ``(position (3,), approach_dir (3,))`` each — the arrow ends at ``position``
    and points along ``approach_dir`` (into the object). Points may contain NaN rows.
    Keyword arguments of :func:`build_figure` (``elev``, ``azim``, ``size_px``…) pass through.
    """
    path = os.fspath(path)
    fig = build_figure(object_points, object_labels, environment_points, boxes, grasps,
                       plane, title, **kwargs)
    parent = os.path.dirname(path)
    if parent:
        os.makedirs(parent, exist_ok=True)
    fig.savefig(path, format="png", dpi=fig.dpi, facecolor="white",
                pil_kwargs={"compress_level": PNG_COMPRESS_LEVEL})
    return path
