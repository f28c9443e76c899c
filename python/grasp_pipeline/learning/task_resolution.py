"""Which perceived object a task's description names, for the reference policy.

The language resolver reads descriptions exactly; the reference policy's descriptions come from
object categories, which perception names more coarsely (an L block, a prism, a stone are
"objects" to it, not boxes) and whose achromatic colours the lighting turns into one another (a
grey stone seen as white). :func:`resolution_ladder` lists what to try, in order, until one
query names exactly one object:

1. the description among all perceived objects;
2. its colour alone ("the red object") among all of them — when it also names a shape;
3. the colour alone among the objects that perception did not name as another shape: those
   seen as the description's shape or as no known shape ("other") — a blob is not the red
   cylinder beside it;
4. for an achromatic colour (:data:`ACHROMATIC`) that names nothing: steps 1–3 again with the
   objects of the other achromatic colours taken as that colour.

Only perception is read (the objects' colour and shape words), never the scene's truth.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Sequence

#: Colours named by brightness alone, which the lighting turns into one another.
ACHROMATIC = ("white", "grey", "silver")
#: The perceived shape of an object perception could not name.
UNNAMED_SHAPE = "other"


def resolution_ladder(description: str, objects: Sequence, language_config) -> list[tuple[str, list]]:
    """(description, objects) queries to try in turn (module doc)."""
    from ..language import parse

    wanted = parse(description, language_config)
    objects = list(objects)
    ladder = _steps(description, wanted, objects)
    if wanted.colour in ACHROMATIC:
        renamed = [replace(o, colour=wanted.colour) if o.colour in ACHROMATIC else o for o in objects]
        ladder += _steps(description, wanted, renamed)
    return ladder


def _steps(description: str, wanted, objects: list) -> list[tuple[str, list]]:
    steps = [(description, objects)]
    if not wanted.colour:
        return steps
    colour_only = f"the {wanted.colour} object"
    if wanted.shape:
        steps.append((colour_only, objects))
    kept = (wanted.shape, UNNAMED_SHAPE) if wanted.shape else (UNNAMED_SHAPE,)
    steps.append((colour_only, [o for o in objects if o.shape in kept]))
    return steps
