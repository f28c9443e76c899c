"""What the benchmarks' plots and summaries share: matplotlib without a display, numbers as
text (``n/a`` for a missing one) and markdown tables."""

from __future__ import annotations

from typing import Optional


def pyplot():
    """``matplotlib.pyplot`` on the Agg backend (files only, no display)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def fmt(v: Optional[float], nd: int = 2) -> str:
    return "n/a" if v is None else f"{v:.{nd}f}"


def short(text: str, n: int = 160) -> str:
    return text if len(text) <= n else text[:n].rstrip() + "…"


def pct(v: Optional[float]) -> str:
    return "n/a" if v is None else f"{100.0 * v:.1f} %"


def md_table(header: list[str], rows: list[list]) -> list[str]:
    """A markdown table (cells' ``|`` escaped, line breaks flattened) and a blank line."""
    out = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    out += ["| " + " | ".join(str(c).replace("|", "\\|").replace("\n", " ") for c in r) + " |" for r in rows]
    return out + [""]
