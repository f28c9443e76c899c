"""The simulated work cell read from the model: table top, tray boxes, tray centre."""

from __future__ import annotations

from functools import lru_cache

import mujoco

from ..assets import asset_path
from ..motion.occupancy import OrientedBox
from ..motion.work_cell import WorkCell

#: The fixed set-up of every scene (robot, floor, table, wall, tray).
SCENE_BASE_XML = "scene_base.xml"
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


@lru_cache(maxsize=1)
def table_top_z_m() -> float:
    """Height of the table top [m] (method.md §8: 0.200 m): the one definition is the fixed
    set-up's model, ``scene_base.xml``'s geom ``table_top``; scenes are built on it."""
    model = mujoco.MjModel.from_xml_path(str(asset_path(SCENE_BASE_XML)))
    g = model.geom(TABLE_TOP_GEOM)
    return float(g.pos[2] + g.size[2])


def read_work_cell(model: mujoco.MjModel, data: mujoco.MjData) -> WorkCell:
    """Table top, fixture boxes (``tray_*`` box geoms) and the tray of a scene model."""
    names = [model.geom(g).name for g in range(model.ngeom)
             if model.geom(g).name.startswith(FIXTURE_PREFIX)
             and model.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX]
    fixtures = tuple(geom_box(model, data, n) for n in names)
    return WorkCell(table=geom_box(model, data, TABLE_TOP_GEOM), fixtures=fixtures,
                    tray_center_m=data.site(TRAY_SITE).xpos.copy(),
                    tray_floor=geom_box(model, data, TRAY_FLOOR_GEOM))
