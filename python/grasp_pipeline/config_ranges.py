"""Allowed ranges of the parameters: one declaration per field, one validator for every set.

Every parameter set (a frozen dataclass loaded from ``config/<section>.yaml``, see
:mod:`.config`) declares ``RANGES``, a mapping of field name to :class:`Range` (bounds, open or
closed ends, unit), and its ``validate()`` starts with :func:`check_ranges`. That checks each
declared field — its type (a whole number for a count, a finite number otherwise; a list: every
item) and its range — and every switch (a bool), and raises a :class:`ConfigError` naming the
section, the parameter, the value and the range, e.g. ``grasp.lift_height_m = 1000000000.0 is
out of range: expected a number in (0, 0.5] m``. Rules between fields (min below max, list
lengths) stay in each set's ``validate()``. The defaults live in the YAML files only; a range
never holds one.

The physical limits several parameters share are named here once — the arm's reach, the
gripper's opening and force (the robot's published figures, :mod:`grasp_pipeline.robot.limits`),
the longest wait, the finest grid step — so every height of the grasp, every opening, every
timeout has the same bound.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import numbers
import typing
from typing import Any, Mapping, NamedTuple, Optional

import numpy as np

from .exceptions import ConfigError
from .messages import brief
from .robot.limits import GRIPPER_MAX_FORCE_N, GRIPPER_MAX_WIDTH_M

#: The Franka Panda reaches 0.855 m: no height, distance or motion of the work cell is longer.
REACH_M = 1.0
#: The longest wait or time limit of one step [s] (simulated or wall-clock).
LONGEST_WAIT_S = 3600.0
#: The finest grid or interpolation step [m]: finer ones make huge grids and paths.
FINEST_STEP_M = 5e-4
#: Largest unsigned 64-bit integer (seeds that reach C++).
UINT64_MAX = 2**64 - 1


class Range(NamedTuple):
    """Allowed values of one parameter: ``lo``/``hi`` (None: unbounded), open ends, unit."""

    lo: Optional[float]
    hi: Optional[float]
    lo_open: bool = False
    hi_open: bool = False
    unit: str = ""

    def contains(self, x: float) -> bool:
        if self.lo is not None and (x < self.lo or (self.lo_open and x == self.lo)):
            return False
        return not (self.hi is not None and (x > self.hi or (self.hi_open and x == self.hi)))

    def text(self, kind: str) -> str:
        """``"a number in (0, 0.5] m"``, ``"an integer >= 1"`` …"""
        if self.lo is None and self.hi is None:
            return "a finite number" if kind == "a number" else kind
        if self.hi is None:
            return f"{kind} {'>' if self.lo_open else '>='} {_fmt(self.lo)}{self.unit}"
        if self.lo is None:
            return f"{kind} {'<' if self.hi_open else '<='} {_fmt(self.hi)}{self.unit}"
        lo_b, hi_b = "(" if self.lo_open else "[", ")" if self.hi_open else "]"
        return f"{kind} in {lo_b}{_fmt(self.lo)}, {_fmt(self.hi)}{hi_b}{self.unit}"


def _fmt(x: float) -> str:
    """1000000 rather than 1e+06 for whole numbers (the bounds users type)."""
    return str(int(x)) if float(x).is_integer() and abs(x) < 1e20 else f"{x:g}"


# ----------------------------------------------------------------------------- named ranges
def length_m(hi: float = REACH_M, *, zero: bool = False, lo: float = 0.0) -> Range:
    """A length or distance: (0, hi] m, or [0, hi] m with ``zero`` (then 0 is allowed)."""
    return Range(lo, hi, lo_open=not zero and lo == 0.0, unit=" m")


def step_m(hi: float = 0.05) -> Range:
    """A grid cell or interpolation step: [FINEST_STEP_M, hi] m."""
    return Range(FINEST_STEP_M, hi, unit=" m")


def duration_s(hi: float = LONGEST_WAIT_S, *, zero: bool = False) -> Range:
    """A wait or time limit: (0, hi] s ([0, hi] with ``zero``)."""
    return Range(0.0, hi, lo_open=not zero, unit=" s")


def angle_rad(hi: float, *, zero: bool = False) -> Range:
    return Range(0.0, hi, lo_open=not zero, unit=" rad")


def count(lo: int, hi: int, unit: str = "") -> Range:
    """A whole number in [lo, hi]."""
    return Range(lo, hi, unit=unit)


#: A share of something: [0, 1].
FRACTION = Range(0.0, 1.0)
#: A share that must be positive: (0, 1].
POSITIVE_FRACTION = Range(0.0, 1.0, lo_open=True)
#: A finger opening, gap or width: [0, the hand's largest opening] m (robot/limits.py).
OPENING_M = Range(0.0, GRIPPER_MAX_WIDTH_M, unit=" m")
#: A grasping force: (0, the hand's largest force] N (robot/limits.py).
FORCE_N = Range(0.0, GRIPPER_MAX_FORCE_N, lo_open=True, unit=" N")
#: A sample or frame rate: (0, 1000] Hz.
RATE_HZ = Range(0.0, 1000.0, lo_open=True, unit=" Hz")
#: A coordinate of the work cell (robot base frame): [-REACH_M, REACH_M] m (and a bit of floor).
CELL_COORDINATE_M = Range(-2.0 * REACH_M, 2.0 * REACH_M, unit=" m")


# ----------------------------------------------------------------------------- the validator
def _scalar_type(typ: Any) -> tuple[Any, int]:
    """(the innermost element type, how many tuple/list levels wrap it)."""
    depth = 0
    while typing.get_origin(typ) in (tuple, list):
        args = [a for a in typing.get_args(typ) if a is not Ellipsis]
        typ = args[0] if args else float
        depth += 1
    return typ, depth


def _kind(typ: Any) -> str:
    return "an integer" if typ is int else "a number"


def _type_problem(value: Any, typ: Any) -> Optional[str]:
    """Why ``value`` is not a value of the number type ``typ`` (None when it is)."""
    got = type(value).__name__
    is_bool = isinstance(value, (bool, np.bool_))
    if typ is int:
        if is_bool or not isinstance(value, numbers.Integral):
            return f"is not an integer (got {got})"
        return None
    if is_bool or not isinstance(value, numbers.Real):
        return f"is not a number (got {got})"
    try:
        finite = math.isfinite(float(value))
    except OverflowError:  # an int beyond float64
        finite = False
    return None if finite else "is not a finite float64 number"


def _check_value(where: str, value: Any, typ: Any, depth: int, rule: Range) -> None:
    if depth:
        if not isinstance(value, (tuple, list)):
            raise ConfigError(f"{where} = {brief(value)} is not a list: expected a list, each item "
                              f"{rule.text(_kind(typ))}")
        for i, item in enumerate(value):
            _check_value(f"{where}[{i}]", item, typ, depth - 1, rule)
        return
    expected = rule.text(_kind(typ))
    problem = _type_problem(value, typ)
    if problem:
        raise ConfigError(f"{where} = {brief(value)} {problem}: expected {expected}")
    if not rule.contains(value):
        raise ConfigError(f"{where} = {brief(value)} is out of range: expected {expected}")


@functools.lru_cache(maxsize=None)
def _hints(cls: type) -> dict:
    return typing.get_type_hints(cls)


def check_ranges(cfg: Any, section: str) -> None:
    """Check every switch and every field ``type(cfg).RANGES`` declares (see the module doc);
    ConfigError ``<section>.<name> = <value> ...`` naming the range."""
    ranges: Mapping[str, Range] = getattr(type(cfg), "RANGES", {})
    hints = _hints(type(cfg))
    for f in dataclasses.fields(cfg):
        value = getattr(cfg, f.name)
        typ = hints[f.name]
        if typ is bool:
            if not isinstance(value, (bool, np.bool_)):
                raise ConfigError(f"{section}.{f.name} = {brief(value)} is not a bool "
                                  f"(got {type(value).__name__}): use true or false")
        elif f.name in ranges:
            scalar, depth = _scalar_type(typ)
            _check_value(f"{section}.{f.name}", value, scalar, depth, ranges[f.name])


def numeric_fields(cls: type) -> list[str]:
    """The fields of a parameter set that hold numbers (or lists of numbers): each needs a range."""
    out = []
    for name, typ in _hints(cls).items():
        scalar, _ = _scalar_type(typ)
        if scalar in (int, float) and name in {f.name for f in dataclasses.fields(cls)}:
            out.append(name)
    return out


def require(ok: bool, section: str, name: str, value: Any, expected: str) -> None:
    """A rule between fields: ConfigError ``<section>.<name> = <value> is out of range:
    expected <expected>`` unless ``ok``."""
    if not ok:
        raise ConfigError(f"{section}.{name} = {brief(value)} is out of range: expected {expected}")


def require_min_max(section: str, name: str, pair: Any) -> None:
    """A ``[min, max]`` pair (each item's range is declared in ``RANGES``): two items, min <= max."""
    require(len(pair) == 2 and pair[0] <= pair[1], section, name, list(pair), "[min, max] with min <= max")
