"""Typed parameter sets loaded from YAML (``config/<name>.yaml``).

Every parameter set is a frozen dataclass whose field names are the YAML keys
(docs/method.md's names where it has a table). ``load_config(cls, "scene_filter")`` reads the
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

import copy
import dataclasses
import difflib
import math
import stat
import typing
from pathlib import Path
from typing import Any, Mapping, TypeVar

import yaml

from .assets import default_config_dir
from .exceptions import ConfigError
from .messages import brief, name, shorten

T = TypeVar("T")

#: Integer parameters must fit in 64 bits (they reach C++ and numpy; seeds are unsigned).
INT_MIN, INT_MAX = -(2**63), 2**64 - 1
#: Largest parameter file read [bytes]: every default file together is about 20 kB (and PyYAML
#: parses about 200 kB per second).
MAX_CONFIG_BYTES = 256_000
#: Most YAML aliases (``*name``) one document may use.
MAX_YAML_ALIASES = 100
#: Most values a document may hold once its aliases are expanded (each alias counts again).
MAX_YAML_VALUES = 100_000


class _LimitedLoader(yaml.SafeLoader):
    """PyYAML's safe loader that refuses more than :data:`MAX_YAML_ALIASES` aliases (a
    "billion laughs" document expands a few aliases into billions of values)."""

    def __init__(self, stream) -> None:
        super().__init__(stream)
        self.aliases = 0

    def compose_node(self, parent, index):
        if self.check_event(yaml.AliasEvent):
            self.aliases += 1
            if self.aliases > MAX_YAML_ALIASES:
                raise ConfigError(f"more than {MAX_YAML_ALIASES} YAML aliases (*name); a parameter "
                                  "file needs none")
        return super().compose_node(parent, index)


def _count_values(data: Any, budget: int) -> int:
    """Values of ``data`` with every alias expanded, counted until ``budget`` is exceeded."""
    stack, n = [data], 0
    while stack and n <= budget:
        item = stack.pop()
        n += 1
        if isinstance(item, dict):
            stack.extend(item.keys())
            stack.extend(item.values())
        elif isinstance(item, (list, tuple)):
            stack.extend(item)
    return n


def _yaml_problem(exc: yaml.YAMLError) -> str:
    """One line: what PyYAML found wrong and where (its own text spans several lines)."""
    problem, mark = getattr(exc, "problem", None), getattr(exc, "problem_mark", None)
    if problem and mark is not None:
        text = f"{problem} (line {mark.line + 1}, column {mark.column + 1})"
    else:
        text = " ".join(str(exc).split())
    return shorten(text, 300)


def parse_yaml(text: str, where: str) -> Any:
    """The value of a YAML text (a file's content, a ``--set`` value) with aliases and size
    limited; ConfigError naming ``where`` when it is not valid YAML or too big once expanded."""
    try:
        data = yaml.load(text, Loader=_LimitedLoader)  # noqa: S506 (a SafeLoader)
    except ConfigError as exc:
        raise ConfigError(f"{where}: {exc}") from None
    except yaml.YAMLError as exc:
        raise ConfigError(f"{where} is not valid YAML: {_yaml_problem(exc)}") from None
    except RecursionError:
        raise ConfigError(f"{where}: nested too deeply to be a parameter file") from None
    if _count_values(data, MAX_YAML_VALUES) > MAX_YAML_VALUES:
        raise ConfigError(f"{where}: more than {MAX_YAML_VALUES} values once its aliases are "
                          "expanded; a parameter file holds a few hundred")
    return data


def _size(n: int) -> str:
    return f"{n / 1e6:.1f} MB" if n >= 1e6 else f"{n / 1e3:.0f} kB"


def _read_text(path: Path) -> str:
    """The UTF-8 text of a regular file of at most :data:`MAX_CONFIG_BYTES` (checked before
    reading: a huge file or a device is refused at once)."""
    try:
        st = path.stat()
    except FileNotFoundError:
        raise ConfigError(f"config file not found: {path}") from None
    except OSError as exc:
        raise ConfigError(f"config file {path} cannot be read ({exc.strerror or exc})") from None
    if stat.S_ISDIR(st.st_mode):
        raise ConfigError(f"config file {path} is a directory; give a YAML file")
    if not stat.S_ISREG(st.st_mode):
        raise ConfigError(f"config file {path} is not a regular file (a device, pipe or socket); "
                          "give a YAML file")
    if st.st_size > MAX_CONFIG_BYTES:
        raise ConfigError(f"config file {path} is {_size(st.st_size)}; a parameter file is at most "
                          f"{_size(MAX_CONFIG_BYTES)} (is it the right file?)")
    try:
        with path.open("rb") as fh:
            raw = fh.read(MAX_CONFIG_BYTES + 1)
    except PermissionError:
        raise ConfigError(f"config file {path} cannot be read (permission denied)") from None
    except OSError as exc:
        raise ConfigError(f"config file {path} cannot be read ({exc.strerror or exc})") from None
    if len(raw) > MAX_CONFIG_BYTES:
        raise ConfigError(f"config file {path} is over {_size(MAX_CONFIG_BYTES)} (is it the right "
                          "file?)")
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError:
        raise ConfigError(f"config file {path} is not UTF-8 text (is it a YAML file?)") from None


#: The mappings of the file texts parsed in this process (text -> mapping): a benchmark worker
#: loads the same default files for every round it runs, and PyYAML's pure-Python loader takes
#: about 10 ms a file. Keyed by the text, so an edited file is parsed anew.
_PARSED: dict[str, dict[str, Any]] = {}
_MAX_PARSED = 64


def read_yaml(path: str | Path) -> dict[str, Any]:
    """Read a YAML mapping (size, aliases and expanded size limited, see :func:`parse_yaml`);
    an empty file is an empty mapping. Each call returns a mapping of its own."""
    path = Path(path)
    text = _read_text(path)
    data = _PARSED.get(text)
    if data is None:
        data = parse_yaml(text, f"config file {path}")
        if data is None:
            data = {}
        if not isinstance(data, dict):
            raise ConfigError(f"config file {path} must hold a mapping of name: value")
        if len(_PARSED) >= _MAX_PARSED:
            _PARSED.clear()
        _PARSED[text] = data
    return copy.deepcopy(data)


_KINDS = {bool: "true or false", int: "an integer", float: "a number", str: "a text"}


def _kind(typ: Any) -> str:
    return _KINDS.get(typ, "a list" if typing.get_origin(typ) in (tuple, list) else str(typ))


def _coerce(label: str, name: str, typ: Any, value: Any) -> Any:
    """Convert ``value`` to the field type, or raise a ConfigError naming ``label.name``."""
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
                raise ConfigError(f"{label}.{name} = {brief(v)}: out of range (|value| must fit in 64 bits)")
            return v
        if typ is float:
            if isinstance(value, bool):
                raise TypeError
            v = float(value)
            if not math.isfinite(v):
                raise ConfigError(f"{label}.{name} = {brief(value)}: expected a finite number")
            return v
        if typ is str:
            if isinstance(value, (dict, list, tuple)):
                raise TypeError
            return str(value)
        if origin in (tuple, list):
            if isinstance(value, str):
                value = parse_yaml(value, f"{label}.{name}")
            if not isinstance(value, (list, tuple)):
                raise TypeError
            args = typing.get_args(typ)
            inner = args[0] if args else float
            seq = [_coerce(label, name, inner, v) for v in value]
            return tuple(seq) if origin is tuple else seq
    except ConfigError:
        raise
    except (TypeError, ValueError, OverflowError):
        raise ConfigError(f"{label}.{name} = {brief(value)}: cannot use it as {_kind(typ)}") from None
    return value


def unknown_names(unknown: list[str], known: list[str], section: str, source: str = "") -> str:
    """The message about parameter names a set does not have: close matches, and where the
    set's names are listed."""
    close = {u: difflib.get_close_matches(u, known, n=1, cutoff=0.7) for u in unknown[:5]}
    hints = [(u, c[0]) for u, c in close.items() if c]
    hint = ""
    if len(unknown) == 1 and hints:
        hint = f" (did you mean {hints[0][1]}?)"
    elif hints:
        hint = " (did you mean " + ", ".join(f"{c} for {name(u)}" for u, c in hints) + "?)"
    where = f" in {source}" if source else ""
    return (f"unknown parameter(s) {shorten(', '.join(map(name, unknown)), 200)}{where} for {section}{hint}; "
            f"its parameters are listed in config/{section}.yaml")


def build_config(cls: type[T], values: Mapping[str, Any], source: str = "", section: str = "") -> T:
    """Instantiate ``cls`` from a mapping, rejecting unknown names; messages name
    ``section.name`` (the class name when no section is given) and ``source``."""
    if not dataclasses.is_dataclass(cls):
        raise TypeError(f"{cls!r} is not a dataclass")
    hints = typing.get_type_hints(cls)
    fields = {f.name: f for f in dataclasses.fields(cls)}
    unknown = sorted(str(k) for k in set(values) - set(fields))
    if unknown:
        raise ConfigError(unknown_names(unknown, list(fields), section or cls.__name__, source))
    label = section or cls.__name__
    kwargs = {k: _coerce(label, k, hints[k], v) for k, v in values.items()}
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
    source = "the overrides (--set)" if overrides and any(k not in {f.name for f in dataclasses.fields(cls)}
                                                          for k in overrides) else str(path or default_file)
    return build_config(cls, values, source=source, section=name)
