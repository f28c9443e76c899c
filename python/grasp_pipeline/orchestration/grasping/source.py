"""Where grasps come from: the :class:`GraspSource` protocol and the :class:`GraspRequest` a
source answers.

The grasp action executes whatever poses a source proposes (position = contact point, rotation
column 0 = approach into the object, column 2 = closing axis, ``width_m``, ``score``), trying
them in order until one can be planned. It never learns who produced them, so a learned grasp
detector replaces the geometric ones by implementing :meth:`GraspSource.propose` — nothing in
motion or execution changes. The sources of the package, one module each:

* :class:`~.any_side.AnySideGraspSource` (``grasp.grasp_source: any_side``) — grasps sampled
  on the points from any side within a tilt limit;
* :class:`~.top_down.GeometricGraspSource` (``grasp.grasp_source: top_down``) — top-down
  grasps fitted to the points, then method.md §3's grasp from the target's box;
* :class:`~.fixed.FixedGraspSource` — a fixed list of poses (known grasps, a replay, a test).

:mod:`.registry` names the ones ``grasp.grasp_source`` (``config/grasp.yaml``) may select.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Optional, Protocol, runtime_checkable

from ...motion.perceived_scene import PerceivedScene
from ...perception.scene_volume import SceneVolume
from ..scene.scene_cloud import SceneCloud


@dataclass(frozen=True)
class GraspRequest:
    """What a source may use to propose grasps of one object.

    ``anchor_xy``: where the user (or the default target list) pointed [m, world];
    ``target``: the selected track (``_core.Track``) or None; ``published``: the best grasp
    the selection published for it (method.md §5) or None; ``scene``: the perceived scene (points,
    boxes); ``max_width_m``: the widest grasp, the gripper's usable opening
    (:func:`~.opening.max_grasp_width_m`);
    ``cloud``: the scene's labelled points
    (:class:`~grasp_pipeline.orchestration.scene.scene_cloud.SceneCloud`) or None;
    ``min_width_m``: the narrowest graspable width; ``reach(grasp, pre_grasp_distance_m)``:
    the grasp with the hand orientation the arm reaches, or None when it reaches neither
    (:class:`~.reach.ArmReach`; None: not checked); ``volume``: the scene volume
    (:class:`~grasp_pipeline.perception.scene_volume.SceneVolume`: which places were seen
    free, occupied, or never seen) or None; ``unknown(points)``: True for the points (N, 3)
    no camera has seen free (from the volume; None: not known)."""

    anchor_xy: tuple[float, float]
    target: Optional[object]
    published: Optional[object]
    scene: PerceivedScene
    max_width_m: float
    cloud: Optional[SceneCloud] = None
    min_width_m: float = 0.005
    reach: Optional[Callable] = None
    volume: Optional[SceneVolume] = None
    unknown: Optional[Callable] = None


@runtime_checkable
class GraspSource(Protocol):
    """Proposes grasps for one object, best first (an empty list: no grasp).

    ``name`` names the source in reports. A source may also say ``top_down_only = True``
    (it proposes only top-down grasps: the selection then keeps method.md §2.6's width guard) and
    keep ``last_refusal``, a sentence on why its last call proposed nothing."""

    name: str

    def propose(self, request: GraspRequest) -> list:
        """Grasp candidates (:class:`~.grasp.Grasp`, or anything with ``R``,
        ``position`` and ``width_m``), best first."""
