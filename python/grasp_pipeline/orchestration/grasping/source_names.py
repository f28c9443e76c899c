"""The names ``grasp.grasp_source`` may take: what the parameter check of
:class:`~grasp_pipeline.orchestration.config.GraspConfig` needs, without the sources themselves
(they use the parameter sets; :mod:`.registry` builds them by name).

The built-in names are :data:`BUILT_IN`; :func:`.registry.register_grasp_source` adds one."""

from __future__ import annotations

import re

#: The sources of this package, in order; the first is the default of ``grasp.grasp_source``.
BUILT_IN: tuple[str, ...] = (
    "any_side",   # grasps from any side within the sampler's tilt limit
    "top_down",   # method.md §3's top-down grasp, fitted to the perceived points
)

_added: list[str] = []


def grasp_source_names() -> tuple[str, ...]:
    """The names ``grasp.grasp_source`` may take."""
    return BUILT_IN + tuple(_added)


def add_grasp_source_name(name: str) -> None:
    """One more name. Raises ValueError for a name that is not a lower-case identifier or is
    taken."""
    if not re.fullmatch(r"[a-z][a-z0-9_]*", name):
        raise ValueError(f"grasp source name {name!r}: use lower-case letters, digits and '_'")
    if name in grasp_source_names():
        raise ValueError(f"grasp source {name!r} is already registered; choose another name")
    _added.append(name)
