"""The parameter sets of ``record``, the learning environment and ``eval``: the run's (as
``bench clutter``) plus ``record`` (what is observed and recorded) and ``env`` (the episodes)."""

from __future__ import annotations

from typing import Optional

#: The sections ``record``, ``eval`` and the environment add to a run's.
LEARNING_SECTIONS = ("record", "env")


def record_overrides(overrides: tuple = (None, ()), fps: Optional[int] = None,
                     image_size: Optional[int] = None) -> tuple:
    """``(config_file, sets)`` with ``--fps`` and ``--image-size`` added as ``--set``s."""
    config_file, sets = overrides
    sets = list(sets)
    if fps is not None:
        sets.append(f"record.record_fps_hz={int(fps)}")
    if image_size is not None:
        sets += [f"record.image_width_px={int(image_size)}", f"record.image_height_px={int(image_size)}"]
    return (config_file, tuple(sets))


def record_settings(overrides: tuple = (None, ())):
    """All sections of a run, ``record`` and ``env`` with ``(config_file, sets)`` overrides."""
    from ..app.sim_system import SECTIONS
    from ..settings import load_settings

    config_file, sets = overrides
    return load_settings(list(SECTIONS) + list(LEARNING_SECTIONS), config_file, list(sets))
