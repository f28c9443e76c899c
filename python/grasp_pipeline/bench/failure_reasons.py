"""Short categories of failure messages and exceptions, the same for every instance of one
cause: what the benchmarks count failures by."""

from __future__ import annotations

import re

_STAGE_PREFIX = re.compile(r"^[A-Z_]+ failed:\s*")
_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def reason_category(message: str, max_len: int = 80) -> str:
    """A short category of a failure message, the same for every instance of one cause: the
    ``STAGE failed:`` prefix removed; the text before the first ``:`` (the details follow it;
    when that head is only one or two words, like "execution stopped", the next part too);
    parenthesised/bracketed details dropped; every number replaced by ``N``.

    ``"CLOSE failed: fingers stalled at 1.2 mm but touch no object"`` →
    ``"fingers stalled at N mm but touch no object"``;
    ``"PLACE failed: execution stopped: unexpected robot contact [('a', 'b')]; the arm …"`` →
    ``"execution stopped: unexpected robot contact"``.
    """
    text = _STAGE_PREFIX.sub("", str(message or "").strip())
    text = text.split(" | ", 1)[0]
    text = re.sub(r"\([^()]*\)|\[[^\[\]]*\]", "", text)  # (details), [details]
    parts = [p.strip() for p in re.split(r":\s", text)]
    head = parts[0]
    if len(head.split()) <= 2 and len(parts) > 1:
        head = f"{head}: {parts[1]}"
    head = head.split(";", 1)[0]
    head = _NUMBER.sub("N", head)
    head = re.sub(r"\s+", " ", head).strip(" ,;.:")
    if len(head) > max_len:
        head = head[:max_len].rstrip() + "…"
    return head or "unspecified"


def exception_category(exc_text: str) -> str:
    """``"ValueError: bad thing 3"`` → ``"ValueError"``."""
    head = str(exc_text or "").split(":", 1)[0].strip()
    return head or "unspecified"
