"""The simulated work cell read from the model: table top, tray boxes, tray centre."""

from __future__ import annotations

import mujoco

from ..motion.occupancy import OrientedBox
from ..motion.work_cell import WorkCell

TABLE_TOP_GEOM = "table_top"
#: Box geoms named like this are the cell's fixtures (the tray's stand, floor and walls).
FIXTURE_PREFIX = "tray_"
TRAY_SITE = "tray_centre"
TRAY_FLOOR_GEOM = "tray_floor"


def geom_box(model: mujoco.MjModel, data: mujoco.MjData, name: str) -> OrientedBox:
    """The world-frame box of the model's box geom ``name``."""
    mujoco.mj_kinematics(model, data)
    g = model.geom(name).id
    return OrientedBox(data.geom_xpos[g].copy(), data.geom_xmat[g].reshape(3, 3).copy(),
                       2.0 * model.geom_size[g].copy())


def read_work_cell(model: mujoco.MjModel, data: mujoco.MjData) -> WorkCell:
    """Table top, fixture boxes (``tray_*`` box geoms) and the tray of a scene model."""
    names = [model.geom(g).name for g in range(model.ngeom)
             if model.geom(g).name.startswith(FIXTURE_PREFIX)
             and model.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX]
    fixtures = tuple(geom_box(model, data, n) for n in names)
    return WorkCell(table=geom_box(model, data, TABLE_TOP_GEOM), fixtures=fixtures,
                    tray_center_m=data.site(TRAY_SITE).xpos.copy(),
                    tray_floor=geom_box(model, data, TRAY_FLOOR_GEOM))
