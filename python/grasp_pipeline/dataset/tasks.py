"""An episode's natural-language task from its target's attributes.

The environment names each episode's target (:mod:`grasp_pipeline.learning.targets`) and words
the task from the object's colour and category: "pick up the red mug and put it in the tray".
The colour is the mesh model's own name for it, else its RGBA named by the same words the
language resolver uses for perceived objects (:func:`grasp_pipeline.language.colours.colour_name`),
so a policy trained on these tasks can be driven by ``run --pick``'s vocabulary.
"""

from __future__ import annotations

from ..language.colours import colour_name

#: What a task names when there is no object to describe.
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
