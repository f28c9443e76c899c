"""Ground truth about the scene's objects — **for evaluation code only**.

Perception, planning and execution must never import this module: they work from depth frames
and the robot's own state, as on a real robot. Scoring code (reports, benchmarks, tests) reads
here what really stands where — including, per pixel of a frame, which object it shows
(:func:`frame_labels`, after :func:`enable_frame_labels` or with ``camera.labels: true``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..robot.frame import Frame
from .exceptions import ModelError, SimError
from .object_geoms import object_body_name
from .world import SimWorld

#: Label of a pixel that shows no scene object (table, robot, tray, background) or has no
#: valid depth.
NO_OBJECT = -1


class FrameLabelsError(SimError, ValueError):
    """No labels for that frame: labelling is off, or it is not the camera's latest frame."""


@dataclass(frozen=True)
class ObjectTruth:
    """The true state of one object at the moment of the query.

    Attributes:
        name, kind: as in the scene's :class:`~.scene_spec.ObjectSpec`.
        size_m: full extents (x, y, z) in the object frame; cylinders (d, d, h).
        T_world_object: 4x4 pose of the object's centre frame now.
        initial_T_world_object: 4x4 pose the scene placed it at.
    """

    name: str
    kind: str
    size_m: tuple[float, float, float]
    T_world_object: np.ndarray
    initial_T_world_object: np.ndarray

    @property
    def position_m(self) -> np.ndarray:
        return self.T_world_object[:3, 3].copy()

    @property
    def top_z_m(self) -> float:
        """Height of the highest point, assuming the object stands upright."""
        return float(self.T_world_object[2, 3] + 0.5 * self.size_m[2])


def object_truths(world: SimWorld) -> list[ObjectTruth]:
    """Every object's true pose and size, in the scene's order."""
    out = []
    for obj in world.scene.objects:
        bid = world.model.body(object_body_name(obj)).id
        T = np.eye(4)
        T[:3, :3] = world.data.xmat[bid].reshape(3, 3)
        T[:3, 3] = world.data.xpos[bid]
        out.append(ObjectTruth(obj.name, obj.kind, tuple(obj.size_m), T, obj.pose()))
    return out


def object_body_id(world: SimWorld, name: str) -> int | None:
    """MuJoCo body id of the object ``name`` of the scene (None: no such object); its pose
    is ``world.data.xpos/xmat[id]`` (what :func:`object_truths` reads)."""
    for obj in world.scene.objects:
        if obj.name == name:
            return int(world.model.body(object_body_name(obj)).id)
    return None


def object_truth(world: SimWorld, name: str) -> ObjectTruth:
    """The truth about one object, by scene name (e.g. ``"blue_cube"``)."""
    for t in object_truths(world):
        if t.name == name:
            return t
    raise KeyError(f"no object {name!r} in scene {world.scene.name!r}; "
                   f"known: {[o.name for o in world.scene.objects]}")


def enable_frame_labels(world: SimWorld, enabled: bool = True) -> None:
    """Make the world's camera compute per-pixel labels from its next capture on (as
    ``camera.labels: true`` does; GL: one more render pass per frame)."""
    camera = _camera(world)
    camera._eval_labels = bool(enabled)
    if not enabled:
        camera._eval_geoms = None


def object_geom_labels(world: SimWorld) -> np.ndarray:
    """(ngeom + 1,) int32: per geom of the model, the index in ``world.scene.objects`` of the
    object it belongs to, else :data:`NO_OBJECT`; the last entry (for geom id -1) too."""
    m = world.model
    body_label = np.full(m.nbody, NO_OBJECT, dtype=np.int32)
    for i, obj in enumerate(world.scene.objects):
        body_label[m.body(object_body_name(obj)).id] = i
    return np.append(body_label[m.geom_bodyid], np.int32(NO_OBJECT))


def frame_labels(world: SimWorld, frame: Frame) -> np.ndarray:
    """(H, W) int32: per pixel of ``frame``, the index in ``world.scene.objects`` of the object
    it shows, :data:`NO_OBJECT` (-1) for anything else and wherever the depth is invalid — so
    the labelled pixels are exactly the labelled valid rows ``v*W + u`` of
    ``frame.points_world``.

    Only the camera's latest frame has labels (the camera keeps one label image), and only
    when labelling was on for its capture; otherwise :class:`FrameLabelsError`.
    """
    camera = _camera(world)
    key = camera._eval_frame_key
    if key is None or key != (frame.index, frame.time_s, frame.T_world_camera.tobytes()):
        latest = "none yet" if key is None else f"frame {key[0]} at t = {key[1]:.4f} s"
        raise FrameLabelsError(
            f"labels exist only for the camera's latest frame; frame {frame.index} "
            f"(t = {frame.time_s:.4f} s) is not it (latest: {latest}) — take the labels right "
            "after the capture")
    geoms = camera._eval_geoms
    if geoms is None:
        raise FrameLabelsError(
            f"frame {frame.index} was captured without labels; call "
            "enable_frame_labels(world) (or set camera.labels: true) before capturing")
    return object_geom_labels(world)[geoms]


def _camera(world: SimWorld):
    if world.camera is None:
        raise ModelError("this SimWorld was created with camera=False: no frames, no labels")
    return world.camera
