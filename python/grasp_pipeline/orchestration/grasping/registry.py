"""The grasp sources a run selects by name: ``grasp.grasp_source`` in ``config/grasp.yaml``.

Each name maps to a factory ``(settings) -> GraspSource`` (``settings``: the run's
:class:`~grasp_pipeline.settings.Settings`); a factory imports its source only when called, so
naming the sources costs no import. A new source is one new module with a class implementing
:class:`~.source.GraspSource`, plus its line in ``_FACTORIES`` below — or, from code outside the
package, :func:`register_grasp_source` before the settings are loaded (they check the name).
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING, Callable

from ...exceptions import ConfigError

if TYPE_CHECKING:
    from ...settings import Settings
    from .source import GraspSource

GraspSourceFactory = Callable[["Settings"], "GraspSource"]


def _any_side(settings: "Settings") -> "GraspSource":
    from .any_side import AnySideGraspSource

    return AnySideGraspSource(settings.grasp_sampler, settings.grasp, settings.grasp_fit, settings.motion)


def _top_down(settings: "Settings") -> "GraspSource":
    from .top_down import GeometricGraspSource

    return GeometricGraspSource(settings.grasp, fit=settings.grasp_fit, motion=settings.motion)


#: name -> factory; the first is the default of ``grasp.grasp_source``
_FACTORIES: dict[str, GraspSourceFactory] = {
    "any_side": _any_side,   # grasps from any side within the sampler's tilt limit
    "top_down": _top_down,   # method.md §3's top-down grasp, fitted to the perceived points
}


def grasp_source_names() -> tuple[str, ...]:
    """The names ``grasp.grasp_source`` may take."""
    return tuple(_FACTORIES)


def register_grasp_source(name: str, factory: GraspSourceFactory) -> None:
    """Make ``grasp.grasp_source: <name>`` build a source with ``factory(settings)``.
    Raises ValueError for a name that is not a lower-case identifier or is taken."""
    if not re.fullmatch(r"[a-z][a-z0-9_]*", name):
        raise ValueError(f"grasp source name {name!r}: use lower-case letters, digits and '_'")
    if name in _FACTORIES:
        raise ValueError(f"grasp source {name!r} is already registered; choose another name")
    _FACTORIES[name] = factory


def make_grasp_source(settings: "Settings") -> "GraspSource":
    """The source ``settings.grasp.grasp_source`` names."""
    name = settings.grasp.grasp_source
    if name not in _FACTORIES:
        raise ConfigError(f"grasp.grasp_source = {name!r}: expected one of {', '.join(_FACTORIES)}")
    return _FACTORIES[name](settings)
