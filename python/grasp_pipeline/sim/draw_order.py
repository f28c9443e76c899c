"""Which geoms a camera frame draws, and in what order: the same image for less rendering.

In software GL (llvmpipe, the headless default) a frame's cost is the triangles set up and the
fragments shaded. Two things in a tabletop scene cost much and show nothing:

* geoms entirely outside the camera's view frustum (most of the arm, seen from its own wrist)
  are still tessellated, lit and clipped: :func:`out_of_view` finds them from their bounding
  spheres, with a margin, so that only geoms that cannot reach a pixel are left out;
* a ground plane drawn first is shaded over the whole image and then painted over by the table;
  drawn last, the depth test rejects its hidden fragments before shading.

Opaque geoms give the same pixels in any drawing order (the depth test keeps the nearest
fragment), and a geom that reaches no pixel adds nothing, so the image is the one MuJoCo's full
scene gives, bit for bit (``tests/python/sim/test_draw_order.py`` renders both).

:class:`DrawOrder` applies this to :func:`mujoco.mjv_updateScene` through the geoms' groups,
changed for the duration of the scene update and restored before it returns.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

#: Margin of the frustum test: bounding radii grow by this factor plus :data:`MARGIN_M`.
RADIUS_FACTOR = 1.05
MARGIN_M = 0.005
#: The geom group the scene update is told to skip (off in the renderer's options).
HIDDEN_GROUP = 5
#: Visual flags that change how geoms are drawn (the planes' pass copies them).
_GEOM_FLAGS = (mujoco.mjtVisFlag.mjVIS_TEXTURE, mujoco.mjtVisFlag.mjVIS_STATIC,
               mujoco.mjtVisFlag.mjVIS_TRANSPARENT, mujoco.mjtVisFlag.mjVIS_CONVEXHULL)


def out_of_view(centres: np.ndarray, radii: np.ndarray, T_world_cam: np.ndarray,
                tan_half_v: float, aspect: float, near_m: float) -> np.ndarray:
    """(N,) bool: the sphere (``centres`` (N, 3) world, ``radii`` (N,)) lies wholly outside the
    view frustum of a camera at ``T_world_cam`` (MuJoCo camera axes: x right, y up, looking
    along -z), vertical half-angle tangent ``tan_half_v``, width/height ``aspect``, near plane
    ``near_m``. Conservative: a sphere near a face counts as in view."""
    R, p = T_world_cam[:3, :3], T_world_cam[:3, 3]
    local = (centres - p) @ R  # camera coordinates
    x, y, depth = local[:, 0], local[:, 1], -local[:, 2]
    r = radii * RADIUS_FACTOR + MARGIN_M
    tan_h = tan_half_v * aspect
    # signed distances to the four side planes (through the eye) and the near plane
    outside = depth < near_m - r
    outside |= (np.abs(x) - tan_h * depth) / math.hypot(1.0, tan_h) > r
    outside |= (np.abs(y) - tan_half_v * depth) / math.hypot(1.0, tan_half_v) > r
    return outside


class DrawOrder:
    """Per frame, the scene of ``model`` as seen from a camera, without the geoms out of view
    and with plane geoms drawn after everything else (see the module doc).

    Args:
        model: the model (its ``geom_group`` is changed during :meth:`update_scene` only).
        option: the renderer's visual options (group :data:`HIDDEN_GROUP` must be off).
        aspect: image width / height.
    """

    def __init__(self, model: mujoco.MjModel, option: mujoco.MjvOption, aspect: float):
        if option.geomgroup[HIDDEN_GROUP]:
            raise ValueError(f"geom group {HIDDEN_GROUP} must be hidden in the renderer's options")
        self.model = model
        self.option = option
        self.aspect = float(aspect)
        self.near_m = float(model.vis.map.znear * model.stat.extent)
        planes = model.geom_type == mujoco.mjtGeom.mjGEOM_PLANE
        # planes and geoms without a bounding radius are never culled
        self._cullable = np.flatnonzero(~planes & (model.geom_rbound > 0))
        self._planes = np.flatnonzero(planes)
        # the second pass adds the planes only: nothing else of the model's decor
        self._no_perturb = mujoco.MjvPerturb()
        self._planes_option = mujoco.MjvOption()
        self._planes_option.geomgroup[:] = option.geomgroup
        for groups in (self._planes_option.sitegroup, self._planes_option.jointgroup,
                       self._planes_option.tendongroup, self._planes_option.actuatorgroup,
                       self._planes_option.flexgroup, self._planes_option.skingroup):
            groups[:] = 0
        self._planes_option.flags[:] = 0
        for flag in _GEOM_FLAGS:  # how geoms look; every decor flag stays off
            self._planes_option.flags[flag] = option.flags[flag]

    def update_scene(self, data: mujoco.MjData, camera: mujoco.MjvCamera,
                     scene: mujoco.MjvScene) -> None:
        """``mujoco.mjv_updateScene`` of ``camera`` (a fixed model camera) into ``scene``,
        ordered and culled as described in the module doc."""
        m = self.model
        group = m.geom_group
        saved = group.copy()
        try:
            group[self._cullable[self._culled(data, int(camera.fixedcamid))]] = HIDDEN_GROUP
            group[self._planes] = HIDDEN_GROUP
            mujoco.mjv_updateScene(m, data, self.option, None, camera,
                                   mujoco.mjtCatBit.mjCAT_ALL, scene)
            if self._planes.size:
                group[:] = HIDDEN_GROUP
                group[self._planes] = saved[self._planes]
                mujoco.mjv_addGeoms(m, data, self._planes_option, self._no_perturb,
                                    int(mujoco.mjtCatBit.mjCAT_ALL), scene)
        finally:
            group[:] = saved

    def _culled(self, data: mujoco.MjData, camera_id: int) -> np.ndarray:
        """(len(cullable),) bool: out of view of camera ``camera_id``."""
        m = self.model
        T = np.eye(4)
        T[:3, :3] = data.cam_xmat[camera_id].reshape(3, 3)
        T[:3, 3] = data.cam_xpos[camera_id]
        tan_half_v = math.tan(math.radians(float(m.cam_fovy[camera_id])) / 2.0)
        ids = self._cullable
        return out_of_view(data.geom_xpos[ids], m.geom_rbound[ids], T, tan_half_v,
                           self.aspect, self.near_m)
