"""An episode's natural-language task from its target's attributes.

The demonstrator labels its own episodes, so the target is known from the simulation (the
object the pick was aimed at, as the pick evaluation names it): "pick up the red mug and put
it in the tray" from the object's colour and category. The colour is the mesh model's own
name for it, else its RGBA named by the same words the language resolver uses for perceived
objects (:func:`grasp_pipeline.language.colours.colour_name`), so a policy trained on these
tasks can be driven by ``run --pick``'s vocabulary.
"""

from __future__ import annotations

from typing import Optional

from ..language.colours import colour_name

#: What an episode whose target is unknown (no object near its anchor) asks for.
UNKNOWN_OBJECT = "object"


def object_phrase(obj) -> str:
    """"red mug": the object's colour name (a mesh model's ``color_name``, else its ``rgba``
    named by :func:`colour_name`; omitted when it has neither) and its category (else its
    kind)."""
    colour = getattr(getattr(obj, "mesh", None), "color_name", "") or ""
    if not colour and getattr(obj, "rgba", None) is not None:
        colour = colour_name(tuple(obj.rgba)[:3])
    category = getattr(obj, "category", "") or getattr(obj, "kind", "") or UNKNOWN_OBJECT
    return f"{colour} {category}".strip().replace("_", " ")


def task_text(template: str, obj) -> str:
    """``template`` (with ``{object}``) filled with :func:`object_phrase` of ``obj``."""
    return template.format(object=object_phrase(obj) if obj is not None else UNKNOWN_OBJECT)


class TargetDescriber:
    """``describe(pick_result) -> (task, object name)``: the target is the object the pick
    evaluation named (``result.object``), else the true object nearest the pick's anchor."""

    def __init__(self, world, objects, template: str) -> None:
        self.world, self.template = world, template
        self.by_name = {o.name: o for o in objects}

    def __call__(self, result) -> tuple[str, Optional[str]]:
        name = getattr(result, "object", None)
        if name is None and getattr(result, "anchor", None):
            from ..evaluation.pick_evaluator import nearest_truth_name

            name = nearest_truth_name(self.world, result.anchor)
        return task_text(self.template, self.by_name.get(name)), name
