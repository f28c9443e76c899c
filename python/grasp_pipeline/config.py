"""Typed parameter sets loaded from YAML (``config/<name>.yaml``).

Every parameter set is a frozen dataclass whose field names are the YAML keys
(SPEC's names where SPEC has a table). ``load_config(cls, "scene_filter")`` reads the
default file shipped with the package, then an optional user file, then
``name=value`` overrides; unknown names and wrong types raise :class:`ConfigError`.

Usage::

    @dataclass(frozen=True)
    class SceneFilterConfig:
        plane_dist_thresh: float = 0.008
        ...

    cfg = load_config(SceneFilterConfig, "scene_filter", overrides={"band": 0.02})
"""

from __future__ import annotations

import dataclasses
import math
import typing
from pathlib import Path
from typing import Any, Mapping, TypeVar

import yaml

from .assets import default_config_dir
from .exceptions import ConfigError

T = TypeVar("T")

#: Integer parameters must fit in 64 bits (they reach C++ and numpy; seeds are unsigned).
INT_MIN, INT_MAX = -(2**63), 2**64 - 1


def read_yaml(path: str | Path) -> dict[str, Any]:
    """Read a YAML mapping; an empty file is an empty mapping."""
    path = Path(path)
    try:
        with path.open("r", encoding="utf-8") as fh:
            data = yaml.safe_load(fh)
    except FileNotFoundError as exc:
        raise ConfigError(f"config file not found: {path}") from exc
    except IsADirectoryError:
        raise ConfigError(f"config file {path} is a directory; give a YAML file") from None
    except PermissionError:
        raise ConfigError(f"config file {path} cannot be read (permission denied)") from None
    except UnicodeDecodeError:
        raise ConfigError(f"config file {path} is not UTF-8 text (is it a YAML file?)") from None
    except yaml.YAMLError as exc:
        raise ConfigError(f"config file {path} is not valid YAML: {exc}") from exc
    if data is None:
        return {}
    if not isinstance(data, dict):
        raise ConfigError(f"config file {path} must hold a mapping of name: value")
    return data


def _coerce(cls_name: str, name: str, typ: Any, value: Any) -> Any:
    """Convert ``value`` to the field type, or raise a ConfigError naming the field."""
    origin = typing.get_origin(typ)
    try:
        if typ is bool:
            if isinstance(value, bool):
                return value
            if isinstance(value, str) and value.lower() in ("true", "false", "1", "0", "yes", "no"):
                return value.lower() in ("true", "1", "yes")
            raise TypeError
        if typ is int:
            if isinstance(value, bool) or (isinstance(value, float) and not value.is_integer()):
                raise TypeError
            v = int(value)
            if not INT_MIN <= v <= INT_MAX:
                raise ConfigError(f"{cls_name}.{name} = {v}: out of range (|value| must fit in 64 bits)")
            return v
        if typ is float:
            if isinstance(value, bool):
                raise TypeError
            v = float(value)
            if not math.isfinite(v):
                raise ConfigError(f"{cls_name}.{name} = {value!r}: expected a finite number")
            return v
        if typ is str:
            return str(value)
        if origin in (tuple, list):
            if isinstance(value, str):
                value = yaml.safe_load(value)
            args = typing.get_args(typ)
            inner = args[0] if args else float
            seq = [_coerce(cls_name, name, inner, v) for v in value]
            return tuple(seq) if origin is tuple else seq
    except ConfigError:
        raise
    except (TypeError, ValueError, OverflowError):
        raise ConfigError(
            f"{cls_name}.{name}: cannot use {value!r} as {getattr(typ, '__name__', typ)}"
        ) from None
    return value


def build_config(cls: type[T], values: Mapping[str, Any], source: str = "") -> T:
    """Instantiate ``cls`` from a mapping, rejecting unknown names."""
    if not dataclasses.is_dataclass(cls):
        raise TypeError(f"{cls!r} is not a dataclass")
    hints = typing.get_type_hints(cls)
    fields = {f.name: f for f in dataclasses.fields(cls)}
    unknown = sorted(set(values) - set(fields))
    if unknown:
        where = f" in {source}" if source else ""
        raise ConfigError(
            f"unknown parameter(s) {', '.join(unknown)}{where} for {cls.__name__}; "
            f"known: {', '.join(sorted(fields))}"
        )
    kwargs = {k: _coerce(cls.__name__, k, hints[k], v) for k, v in values.items()}
    obj = cls(**kwargs)
    validate = getattr(obj, "validate", None)
    if callable(validate):
        validate()
    return obj


def load_config(
    cls: type[T],
    name: str,
    path: str | Path | None = None,
    overrides: Mapping[str, Any] | None = None,
) -> T:
    """Load parameter set ``name``: packaged defaults < ``path`` < ``overrides``."""
    values: dict[str, Any] = {}
    default_file = default_config_dir() / f"{name}.yaml"
    if default_file.exists():
        values.update(read_yaml(default_file))
    if path is not None:
        values.update(read_yaml(path))
    if overrides:
        values.update(overrides)
    return build_config(cls, values, source=str(path or default_file))
