"""The figures every benchmark result is made of: statistics of a sample (:class:`Stats`),
rates, failures by stage and reason (:class:`StageFailures`). Pure functions; ``None`` (JSON
null) where a figure is undefined, never NaN."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Iterable, Mapping, Optional

import numpy as np

#: Pick stages in pipeline order (for tables and plots).
STAGE_ORDER = ("SCENE", "PLANE", "DETECT", "NOT_ATTEMPTED", "SELECT", "GRASP", "PRE_GRASP",
               "APPROACH", "CLOSE", "LIFT", "DONE", "PLACE", "VERIFY")


@dataclass(frozen=True)
class Stats:
    """Statistics of the finite values of a sample (in the unit its field names); None when
    there are none."""

    n: int
    median: Optional[float]
    p90: Optional[float]
    mean: Optional[float]
    max: Optional[float]


@dataclass(frozen=True)
class StageFailures:
    """The failures at one stage: how many, and how many of each reason (most frequent first)."""

    count: int
    reasons: dict[str, int]


def _finite(values: Iterable) -> list[float]:
    return [float(v) for v in values if v is not None and math.isfinite(float(v))]


def _percentile(values: list[float], q: float) -> Optional[float]:
    return float(np.percentile(np.asarray(values, float), q)) if values else None


def _round4(x: Optional[float]) -> Optional[float]:
    return None if x is None else round(x, 4)


def stats(values: Iterable) -> Stats:
    """:class:`Stats` of the finite values (rounded to 4 decimals)."""
    v = _finite(values)
    return Stats(n=len(v), median=_round4(_percentile(v, 50)), p90=_round4(_percentile(v, 90)),
                 mean=_round4(sum(v) / len(v)) if v else None, max=_round4(max(v)) if v else None)


def rate(num: int, den: int) -> Optional[float]:
    """``num / den`` rounded to 4 decimals; None when ``den`` is 0."""
    return None if den == 0 else round(num / den, 4)


def failures_by_stage(rows: Iterable[Mapping], ok_key: str = "picked") -> dict[str, StageFailures]:
    """The rows whose ``ok_key`` is false (objects not picked, failed attempts; each with its
    ``stage`` and ``reason``), by stage (pipeline order) and reason (most frequent first)."""
    counts: dict[str, int] = {}
    reasons: dict[str, dict[str, int]] = {}
    for o in rows:
        if o[ok_key]:
            continue
        counts[o["stage"]] = counts.get(o["stage"], 0) + 1
        by_reason = reasons.setdefault(o["stage"], {})
        by_reason[o["reason"]] = by_reason.get(o["reason"], 0) + 1
    order = {s: i for i, s in enumerate(STAGE_ORDER)}
    return {s: StageFailures(counts[s], dict(sorted(reasons[s].items(), key=lambda kv: (-kv[1], kv[0]))))
            for s in sorted(counts, key=lambda s: (order.get(s, len(order)), s))}
