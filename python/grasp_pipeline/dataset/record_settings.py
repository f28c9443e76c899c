"""The parameter sets of ``record``: the run's (as ``bench clutter``) plus ``record``."""

from __future__ import annotations


def record_settings(overrides: tuple = (None, ())):
    """All sections of a run and ``record`` with ``(config_file, sets)`` overrides."""
    from ..app.sim_system import SECTIONS
    from ..settings import load_settings

    config_file, sets = overrides
    return load_settings(list(SECTIONS) + ["record"], config_file, list(sets))
