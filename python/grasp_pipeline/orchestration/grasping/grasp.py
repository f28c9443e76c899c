"""The typed grasp every grasp source proposes and the grasp action executes.

Convention (the same as the perception core's ``BestGrasp``): ``position`` is the contact
point — the centre between the finger pads when they close — in the world frame [m];
``R`` is a rotation whose column 0 is the approach direction (pointing *into* the object),
column 2 the closing axis (the line the fingers move along) and column 1 = column 2 × column 0.
``width_m`` is the object's width across the pads. ``tcp_R``, when a source has chosen it,
is the exact TCP orientation to reach the grasp with (the closing axis has no sign; a source
that checked the arm's reach knows which of the two hand orientations the arm reaches).
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field
from typing import Optional

import numpy as np


class GraspKind(enum.Enum):
    """How the hand comes in: straight down the table normal, tilted from it, or from the side."""

    TOP_DOWN = "top_down"
    TILTED = "tilted"
    SIDE = "side"


#: Approaches within this angle of the table normal count as top-down [deg].
TOP_DOWN_TOLERANCE_DEG = 2.0
#: Approaches tilted more than this from the table normal are side grasps [deg].
SIDE_TILT_DEG = 70.0


@dataclass(frozen=True)
class Grasp:
    """One grasp (see the module doc for the frame convention).

    ``score``: the source's predicted quality in [0, 1] (0 when it has none, e.g. a box
    grasp); ``source``: the name of the source that proposed it; ``target_tid``: the track it
    is for; ``tilt_deg``: the approach's angle from the table normal (set by the source,
    which knows the table); ``notes``: the source's words on it (for reports and logs)."""

    R: np.ndarray
    position: np.ndarray
    width_m: float
    score: float = 0.0
    source: str = ""
    target_tid: Optional[int] = None
    tilt_deg: float = 0.0
    tcp_R: Optional[np.ndarray] = None
    notes: tuple = field(default_factory=tuple)

    def __post_init__(self) -> None:
        R = np.asarray(self.R, dtype=float).reshape(3, 3)
        p = np.asarray(self.position, dtype=float).reshape(3)
        if not (np.all(np.isfinite(R)) and np.all(np.isfinite(p))):
            raise ValueError("a grasp needs a finite rotation and position")
        if not np.isfinite(self.width_m) or self.width_m < 0:
            raise ValueError(f"a grasp width must be a non-negative number, got {self.width_m}")
        object.__setattr__(self, "R", R)
        object.__setattr__(self, "position", p)
        if self.tcp_R is not None:
            object.__setattr__(self, "tcp_R", np.asarray(self.tcp_R, dtype=float).reshape(3, 3))

    @property
    def approach(self) -> np.ndarray:
        """Unit approach direction (into the object)."""
        return self.R[:, 0].copy()

    @property
    def closing(self) -> np.ndarray:
        """Unit closing axis (sign irrelevant)."""
        return self.R[:, 2].copy()

    @property
    def kind(self) -> GraspKind:
        if self.tilt_deg <= TOP_DOWN_TOLERANCE_DEG:
            return GraspKind.TOP_DOWN
        return GraspKind.SIDE if self.tilt_deg > SIDE_TILT_DEG else GraspKind.TILTED

    @classmethod
    def from_axes(cls, approach, closing, position, width_m: float, **kw) -> "Grasp":
        """A grasp from its approach and closing axes (the closing axis is made orthogonal
        to the approach)."""
        a = np.asarray(approach, dtype=float)
        a = a / np.linalg.norm(a)
        c = np.asarray(closing, dtype=float)
        c = c - float(c @ a) * a
        norm = float(np.linalg.norm(c))
        if norm < 1e-9:
            raise ValueError("closing axis parallel to the approach: degenerate grasp")
        c /= norm
        return cls(np.column_stack([a, np.cross(c, a), c]), position, width_m, **kw)

    @classmethod
    def of(cls, grasp, source: str = "", target_tid: Optional[int] = None, plane_n=None) -> "Grasp":
        """A :class:`Grasp` from any object with ``R``, ``position`` and ``width_m`` (a
        ``_core.BestGrasp``, a Grasp); ``plane_n``: the table normal for ``tilt_deg``."""
        if isinstance(grasp, Grasp):
            return grasp
        R = np.asarray(grasp.R, dtype=float)
        tilt = 0.0 if plane_n is None else tilt_deg(R[:, 0], plane_n)
        return cls(R, np.asarray(grasp.position, dtype=float), float(grasp.width_m),
                   float(getattr(grasp, "score", 0.0)), source, target_tid, tilt)


def tilt_deg(approach, plane_n) -> float:
    """Angle [deg] between an approach direction (into the object) and the table's downward
    normal: 0 for a top-down approach, 90 for a horizontal one."""
    a = np.asarray(approach, dtype=float)
    n = np.asarray(plane_n, dtype=float)
    cos = float(-(a @ n) / (np.linalg.norm(a) * np.linalg.norm(n)))
    return float(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))))
