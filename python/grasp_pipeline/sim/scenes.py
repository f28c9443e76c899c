"""Scenes: the reference scene of method.md §8 and a seeded random scene generator.

The fixed set-up (floor, table with its top at 0.200 m, wall, tray) lives in
``sim/scene_base.xml``; a :class:`~.scene_spec.SceneSpec` only lists the graspable objects and
the start joints. Objects stand upright on the table; their centre is at
``table_top_z_m + height / 2`` (plus :data:`REST_CLEARANCE_M`, so nothing starts in contact).
"""

from __future__ import annotations

import math

import numpy as np

from .config import SimConfig, load_sim_config
from .exceptions import SceneError
from ..robot.description import READY_Q
from .scene_spec import OBJECT_KINDS, ObjectSpec, SceneSpec
from .work_cell import table_top_z_m

#: Gap left under an object when it is placed, so it settles onto the table without a jolt.
REST_CLEARANCE_M = 0.0005
#: Attempts of the rejection sampler before the generator gives up.
MAX_PLACEMENT_ATTEMPTS = 2000

BLUE = (0.10, 0.25, 0.85, 1.0)
RED = (0.85, 0.12, 0.10, 1.0)
GREEN = (0.10, 0.65, 0.20, 1.0)
PALETTE: tuple[tuple[float, float, float, float], ...] = (
    BLUE, RED, GREEN,
    (0.95, 0.75, 0.10, 1.0),  # yellow
    (0.60, 0.20, 0.70, 1.0),  # purple
    (0.95, 0.45, 0.10, 1.0),  # orange
)

# method.md §8: 5 cm cubes, a cylinder of about 5 cm diameter (height ours: 6 cm).
REFERENCE_CUBE_SIZE_M = 0.05
REFERENCE_CYLINDER_DIAMETER_M = 0.05
REFERENCE_CYLINDER_HEIGHT_M = 0.06


def _resting_z(table_top_z_m: float, height_m: float) -> float:
    return table_top_z_m + 0.5 * height_m + REST_CLEARANCE_M


def reference_scene(config: SimConfig | None = None) -> SceneSpec:
    """method.md §8: blue cube near (0.56, -0.03), red cube near (0.46, -0.10), green
    cylinder near (0.52, 0.09) on the table (top at 0.200 m); start joints :data:`READY_Q`."""
    cfg = config if config is not None else load_sim_config()
    top = table_top_z_m()
    c, d, h = REFERENCE_CUBE_SIZE_M, REFERENCE_CYLINDER_DIAMETER_M, REFERENCE_CYLINDER_HEIGHT_M
    objects = (
        ObjectSpec("blue_cube", "cube", (c, c, c), (0.56, -0.03, _resting_z(top, c)),
                   yaw_rad=math.radians(20.0), rgba=BLUE),
        ObjectSpec("red_cube", "cube", (c, c, c), (0.46, -0.10, _resting_z(top, c)),
                   yaw_rad=math.radians(-10.0), rgba=RED),
        ObjectSpec("green_cylinder", "cylinder", (d, d, h), (0.52, 0.09, _resting_z(top, h)),
                   rgba=GREEN),
    )
    return SceneSpec("reference", objects, top, tuple(float(v) for v in READY_Q))


def _uniform(rng: np.random.Generator, rng_range: tuple[float, ...]) -> float:
    return float(rng.uniform(rng_range[0], rng_range[1]))


def _random_object(rng: np.random.Generator, cfg: SimConfig, index: int,
                   xy: tuple[float, float]) -> ObjectSpec:
    kind = OBJECT_KINDS[int(rng.integers(len(OBJECT_KINDS)))]
    if kind == "cube":
        s = _uniform(rng, cfg.cube_size_m)
        size = (s, s, s)
    elif kind == "cuboid":
        size = (_uniform(rng, cfg.cuboid_width_m), _uniform(rng, cfg.cuboid_width_m),
                _uniform(rng, cfg.cuboid_height_m))
    else:
        dia = _uniform(rng, cfg.cylinder_diameter_m)
        size = (dia, dia, _uniform(rng, cfg.cylinder_height_m))
    yaw = float(rng.uniform(-math.pi, math.pi)) if kind != "cylinder" else 0.0
    pos = (xy[0], xy[1], _resting_z(table_top_z_m(), size[2]))
    return ObjectSpec(f"{kind}_{index}", kind, size, pos, yaw_rad=yaw,
                      rgba=PALETTE[index % len(PALETTE)])


def random_scene(seed: int, n_objects: int | None = None,
                 config: SimConfig | None = None) -> SceneSpec:
    """A seeded random scene: 1-6 objects (cubes, cuboids, cylinders, sizes from ``sim.yaml``),
    random yaw, centres inside the reachable region and at least ``min_separation_m`` apart.

    The same seed always gives the same scene. Raises :class:`SceneError` when the objects
    cannot be placed (too many for the region at that separation).
    """
    cfg = config if config is not None else load_sim_config()
    rng = np.random.default_rng(seed)
    lo, hi = int(cfg.object_count[0]), int(cfg.object_count[1])
    n = int(rng.integers(lo, hi + 1)) if n_objects is None else int(n_objects)
    if n < 1:
        raise SceneError(f"a scene needs at least one object, got n_objects={n}")
    for _attempt in range(MAX_PLACEMENT_ATTEMPTS):
        centres: list[tuple[float, float]] = []
        for _ in range(n):
            for _try in range(200):
                xy = (_uniform(rng, cfg.region_x_m), _uniform(rng, cfg.region_y_m))
                if all(math.dist(xy, c) >= cfg.min_separation_m for c in centres):
                    centres.append(xy)
                    break
            else:
                break
        if len(centres) == n:
            objects = tuple(_random_object(rng, cfg, i, xy) for i, xy in enumerate(centres))
            return SceneSpec(f"random_{seed}", objects, table_top_z_m(),
                             tuple(float(v) for v in READY_Q), seed=seed)
    raise SceneError(
        f"cannot place {n} objects {cfg.min_separation_m} m apart in x {cfg.region_x_m}, "
        f"y {cfg.region_y_m}; use fewer objects or a smaller min_separation_m")
