"""The simulated work cell's tray (floor 280 x 280 mm at z = 0.2 m, walls 30 mm high) as a
:class:`WorkCell`, for the tray tests (no simulator)."""

import numpy as np

from grasp_pipeline.motion.occupancy import OrientedBox
from grasp_pipeline.motion.work_cell import WorkCell


def box(c, e) -> OrientedBox:
    return OrientedBox(np.array(c, float), np.eye(3), np.array(e, float))


FIXTURES = (box([0.34, 0.58, 0.095], [0.28, 0.28, 0.19]), box([0.34, 0.58, 0.195], [0.28, 0.28, 0.01]),
            box([0.205, 0.58, 0.215], [0.01, 0.28, 0.03]), box([0.475, 0.58, 0.215], [0.01, 0.28, 0.03]),
            box([0.34, 0.445, 0.215], [0.26, 0.01, 0.03]), box([0.34, 0.715, 0.215], [0.26, 0.01, 0.03]))
CELL = WorkCell(table=box([0.5, 0.0, 0.19], [0.6, 1.0, 0.02]), fixtures=FIXTURES,
                tray_center_m=np.array([0.34, 0.58, 0.2]), tray_floor=FIXTURES[1])
FLOOR_Z = 0.2


def box_points(x, y, w, d, h, z0=FLOOR_Z, step=0.004) -> np.ndarray:
    """Top-surface points of a w x d x h box standing at (x, y) on ``z0`` (what a camera above sees)."""
    X, Y = np.meshgrid(np.arange(x - w / 2, x + w / 2 + 1e-9, step), np.arange(y - d / 2, y + d / 2 + 1e-9, step))
    return np.c_[X.ravel(), Y.ravel(), np.full(X.size, z0 + h)]


def solid_points(w, d, h, step=0.005) -> np.ndarray:
    """A w x d x h box's points filling it, centred on the origin."""
    g = [np.arange(-a / 2, a / 2 + 1e-9, step) for a in (w, d, h)]
    X, Y, Z = np.meshgrid(*g, indexing="ij")
    return np.c_[X.ravel(), Y.ravel(), Z.ravel()]


def floor_points(step=0.005) -> np.ndarray:
    """The tray floor seen from above (inside its walls)."""
    return box_points(0.34, 0.58, 0.25, 0.25, 0.0, step=step)
