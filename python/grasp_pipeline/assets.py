"""Locating package data: the MuJoCo assets (``sim/``) and the default YAML configs.

In an installed wheel the assets live inside the package (``grasp_pipeline/assets``
and ``grasp_pipeline/default_config``); in a source checkout (``PYTHONPATH=python``)
they are the repository's top-level ``sim/`` and ``config/`` folders.
"""

from __future__ import annotations

from pathlib import Path

_PACKAGE_DIR = Path(__file__).resolve().parent
_REPO_DIR = _PACKAGE_DIR.parent.parent


def _first_existing(*candidates: Path) -> Path:
    for c in candidates:
        if c.is_dir():
            return c
    raise FileNotFoundError(
        "grasp_pipeline data folder not found; looked in: "
        + ", ".join(str(c) for c in candidates)
        + ". Reinstall the package with `pip install .`."
    )


def assets_dir() -> Path:
    """Folder holding the MuJoCo models and scene templates."""
    return _first_existing(_PACKAGE_DIR / "assets", _REPO_DIR / "sim")


def default_config_dir() -> Path:
    """Folder holding the default YAML parameter files."""
    return _first_existing(_PACKAGE_DIR / "default_config", _REPO_DIR / "config")


def asset_path(name: str) -> Path:
    """Path of one asset file, e.g. ``asset_path("panda.xml")``."""
    p = assets_dir() / name
    if not p.exists():
        raise FileNotFoundError(f"asset {name!r} not found in {assets_dir()}")
    return p
