"""How accurate the object estimates of ``bench grasp`` are against the ground truth: error
statistics per metric (:class:`Accuracy`) and what the scan improves over the rough view
(:class:`ScanImprovement`), from the objects' error rows (evaluation code)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping, Optional, Sequence

from .figures import Stats, stats

#: Object kinds whose footprint defines a yaw (cylinders are round).
YAW_KINDS = ("cube", "cuboid")
#: Accuracy metrics: JSON name → key in a score row.
ACCURACY_METRICS = {"center_mm": "center_err_mm", "width_mm": "width_err_mm",
                    "height_mm": "height_err_mm", "yaw_deg": "yaw_err_deg",
                    "pca_tilt_deg": "pca_tilt_deg"}


@dataclass(frozen=True)
class Accuracy:
    """Error statistics over some objects' estimates (yaw only for cubes and cuboids)."""

    objects: int
    center_mm: Stats
    width_mm: Stats
    height_mm: Stats
    yaw_deg: Stats
    pca_tilt_deg: Stats


@dataclass(frozen=True)
class MedianPair:
    """One metric's median error on the same objects, seen obliquely (rough view) and NADIR."""

    oblique_median: Optional[float]
    nadir_median: Optional[float]
    n: int


@dataclass(frozen=True)
class ScanImprovement:
    """The improvement the scan buys: the same objects, oblique (rough view) vs NADIR."""

    objects: int
    center_mm: MedianPair
    width_mm: MedianPair
    height_mm: MedianPair
    yaw_deg: MedianPair
    pca_tilt_deg: MedianPair


def _counts_for(metric: str, row: Mapping) -> bool:
    return metric != "yaw_deg" or row["kind"] in YAW_KINDS


def accuracy(rows: Sequence[Mapping], key: str, nadir_only: bool) -> Accuracy:
    """Error statistics over the objects' ``key`` errors (``rough_errors``/``nadir_errors``);
    ``nadir_only``: only objects whose estimate is NADIR; yaw only for cubes and cuboids."""
    sel = [(r, r[key]) for r in rows if r.get(key)]
    if nadir_only:
        sel = [(r, e) for r, e in sel if e.get("quality") == "NADIR"]
    return Accuracy(objects=len(sel), **{name: stats(e[field] for r, e in sel if _counts_for(name, r))
                                         for name, field in ACCURACY_METRICS.items()})


def scan_improvement(rows: Sequence[Mapping]) -> ScanImprovement:
    """The objects with both a rough-view and a NADIR estimate: the median error of each."""
    paired = [o for o in rows if o.get("rough_errors") and o.get("nadir_errors")
              and o["nadir_errors"].get("quality") == "NADIR"]
    pairs = {}
    for name, field in ACCURACY_METRICS.items():
        sel = [o for o in paired if _counts_for(name, o)]
        pairs[name] = MedianPair(oblique_median=stats(o["rough_errors"][field] for o in sel).median,
                                 nadir_median=stats(o["nadir_errors"][field] for o in sel).median,
                                 n=len(sel))
    return ScanImprovement(objects=len(paired), **pairs)
