"""``run --pick "the red mug" --pick "the tallest box"``: the descriptions → the objects to pick.

Every description is resolved against the same perceived objects (after the rough view and
the scan), before anything is picked; a refusal of any of them (unknown word, no match,
ambiguous, two descriptions naming one object) ends the run before the first pick.
"""

from __future__ import annotations

from typing import Sequence

from ..results import PickResolution
from .attributes import PerceivedObject, relative_sizes
from .config import LanguageConfig
from .exceptions import SameObjectError
from .resolver import describe, resolve


def resolution(description: str, obj: PerceivedObject, size: str) -> PickResolution:
    """The report record of one resolved description."""
    return PickResolution(description=description, tid=obj.tid, described=describe(obj),
                          colour=obj.colour, shape=obj.shape, size=size,
                          center=list(obj.center_m), extents=list(obj.extents_m),
                          distance_m=obj.distance_m)


def resolve_picks(descriptions: Sequence[str], objects: Sequence[PerceivedObject],
                  out: list, config: LanguageConfig | None = None) -> list[tuple[float, float]]:
    """Resolve each description in order, appending its :class:`PickResolution` to ``out``
    (kept when a later one is refused); returns the (x, y) of the objects to pick, in order."""
    cfg = config or LanguageConfig()
    sizes = relative_sizes(objects, cfg)
    named: dict[int, str] = {}
    targets = []
    for d in descriptions:
        obj = resolve(d, objects, cfg)
        if obj.tid in named:
            raise SameObjectError(f"{named[obj.tid]!r} and {d!r} both name #{obj.tid} "
                                  f"({describe(obj)}); an object can be picked once")
        named[obj.tid] = d
        out.append(resolution(d, obj, sizes.get(obj.tid, "")))
        targets.append(obj.xy)
    return targets
