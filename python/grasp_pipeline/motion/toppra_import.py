"""TOPP-RA imported without loading matplotlib's pyplot.

``toppra`` imports ``matplotlib.pyplot`` when it is imported, for plotting helpers that the
timing here never calls; in a process that times paths that import is about a quarter of all
its imports' CPU (0.4 s, for a simulated round of 10-20 s). :func:`import_toppra`
imports toppra with a stand-in for pyplot that imports the real one the first time anything
on it is used (a toppra plot still works), and takes the stand-in back out of
``sys.modules`` straight after, so that any later ``import matplotlib.pyplot`` gets the real
module.
"""

from __future__ import annotations

import sys
import threading
import types

_LOCK = threading.Lock()


class _PyplotOnFirstUse(types.ModuleType):
    """Stands for ``matplotlib.pyplot`` in toppra's modules: the real pyplot is imported at
    the first attribute asked of it."""

    def __getattr__(self, name: str):
        import matplotlib.pyplot as pyplot  # the real one: the stand-in has left sys.modules

        return getattr(pyplot, name)


def import_toppra() -> types.ModuleType:
    """The ``toppra`` package with its ``algorithm`` and ``constraint`` modules imported,
    pyplot not loaded unless it already was."""
    with _LOCK:
        if "toppra" not in sys.modules:
            _import_with_pyplot_deferred()
    import toppra
    import toppra.algorithm  # noqa: F401 (imported for its side effect on the package)
    import toppra.constraint  # noqa: F401

    return toppra


def _import_with_pyplot_deferred() -> None:
    placed: list[str] = []
    if "matplotlib.pyplot" not in sys.modules:
        stand_in = _PyplotOnFirstUse("matplotlib.pyplot")
        if "matplotlib" not in sys.modules:  # nor the package: a bare one that holds pyplot
            package = types.ModuleType("matplotlib")
            package.pyplot = stand_in
            sys.modules["matplotlib"] = package
            placed.append("matplotlib")
        sys.modules["matplotlib.pyplot"] = stand_in
        placed.append("matplotlib.pyplot")
    try:
        import toppra
        import toppra.algorithm  # noqa: F401
        import toppra.constraint  # noqa: F401
    finally:
        for name in placed:
            sys.modules.pop(name, None)
