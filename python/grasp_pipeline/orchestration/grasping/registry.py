"""The grasp sources a run selects by name: ``grasp.grasp_source`` in ``config/grasp.yaml``.

Each name maps to a factory ``(settings) -> GraspSource`` (``settings``: the run's
:class:`~grasp_pipeline.settings.Settings`); a factory imports its source only when called, so
naming the sources costs no import. A new source is one new module with a class implementing
:class:`~.source.GraspSource`, plus its name in :data:`.source_names.BUILT_IN` and its line in
``_FACTORIES`` below — or, from code outside the package, :func:`register_grasp_source` before
the settings are loaded (they check the name against :mod:`.source_names`, which the parameter
sets import instead of this module: the sources import the parameter sets).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Callable

from ...exceptions import ConfigError
from .source_names import add_grasp_source_name, grasp_source_names

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


#: name -> factory, the built-in ones in the order of :data:`.source_names.BUILT_IN`
_FACTORIES: dict[str, GraspSourceFactory] = {
    "any_side": _any_side,
    "top_down": _top_down,
}

__all__ = ["grasp_source_names", "make_grasp_source", "register_grasp_source"]


def register_grasp_source(name: str, factory: GraspSourceFactory) -> None:
    """Make ``grasp.grasp_source: <name>`` build a source with ``factory(settings)``.
    Raises ValueError for a name that is not a lower-case identifier or is taken."""
    add_grasp_source_name(name)
    _FACTORIES[name] = factory


def make_grasp_source(settings: "Settings") -> "GraspSource":
    """The source ``settings.grasp.grasp_source`` names."""
    name = settings.grasp.grasp_source
    if name not in _FACTORIES:
        raise ConfigError(f"grasp.grasp_source = {name!r}: expected one of {', '.join(_FACTORIES)}")
    return _FACTORIES[name](settings)
