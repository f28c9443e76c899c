"""Resolve a short description ("the red mug", "the tallest box") against perceived objects.

An object fits when its colour, shape and relative size (:func:`~.attributes.relative_sizes`)
equal the words given. A superlative (tallest, nearest, smallest, largest) then keeps the
extreme one among those that fit — unless the runner-up is within ``superlative_tie_m``
(height, distance) or ``superlative_tie_volume_ratio`` (volume) of it: then the description
is ambiguous. Exactly one object → that object; none → :class:`NoMatchError`; more than one →
:class:`AmbiguousDescriptionError`; both messages list what was seen
("seen: #1 red box (large), #2 blue cylinder, ...").
"""

from __future__ import annotations

from typing import Mapping, Sequence

from .attributes import PerceivedObject, relative_sizes
from .config import LanguageConfig
from .exceptions import AmbiguousDescriptionError, NoMatchError
from .parse import Wanted, parse

#: superlative → (measure of an object, True when the largest value wins)
_MEASURES = {
    "tallest": (lambda o: o.height_m, True),
    "nearest": (lambda o: o.distance_m, False),
    "smallest": (lambda o: o.volume_m3, False),
    "largest": (lambda o: o.volume_m3, True),
}


def describe(obj: PerceivedObject, size: str = "") -> str:
    """The object in words: "the red mug", "the small blue cylinder", "the object"."""
    colour = "" if obj.colour == "unknown" else obj.colour
    noun = "object" if obj.shape == "other" else obj.shape
    return " ".join(w for w in ("the", size, colour, noun) if w)


def seen_list(objects: Sequence[PerceivedObject], sizes: Mapping[int, str]) -> str:
    """``#1 red box (large), #2 blue cylinder`` (``nothing`` when empty)."""
    if not objects:
        return "nothing"
    return ", ".join(f"#{o.tid} {describe(o)[4:]}" + (f" ({sizes[o.tid]})" if sizes.get(o.tid) else "")
                     for o in sorted(objects, key=lambda o: o.tid))


def _fits(o: PerceivedObject, wanted: Wanted, sizes: Mapping[int, str]) -> bool:
    return ((wanted.colour is None or o.colour == wanted.colour)
            and (wanted.shape is None or o.shape == wanted.shape)
            and (wanted.size is None or sizes.get(o.tid) == wanted.size))


def _extreme(cands: list[PerceivedObject], superlative: str, cfg: LanguageConfig) -> list[PerceivedObject]:
    """The extreme candidate, or it with every candidate tied with it."""
    measure, largest = _MEASURES[superlative]
    ranked = sorted(cands, key=measure, reverse=largest)
    best = measure(ranked[0])
    if superlative in ("smallest", "largest"):
        tol = cfg.superlative_tie_volume_ratio * abs(best)
    else:
        tol = cfg.superlative_tie_m
    return [o for o in ranked if abs(measure(o) - best) <= tol]


def resolve(description: str, objects: Sequence[PerceivedObject],
            config: LanguageConfig | None = None) -> PerceivedObject:
    """The one perceived object ``description`` names (see the module doc).

    Raises :class:`~.exceptions.UnknownWordError` / ``DescriptionError`` (a description that
    cannot be read), :class:`NoMatchError`, :class:`AmbiguousDescriptionError`."""
    cfg = config or LanguageConfig()
    wanted = parse(description, cfg)
    objects = list(objects)
    sizes = relative_sizes(objects, cfg)
    cands = [o for o in objects if _fits(o, wanted, sizes)]
    if wanted.superlative and len(cands) > 1:
        cands = _extreme(cands, wanted.superlative, cfg)
    if not cands:
        raise NoMatchError(f"{description!r}: no {wanted.phrase()} seen; seen: {seen_list(objects, sizes)}")
    if len(cands) > 1:
        which = ", ".join(f"#{o.tid}" for o in cands)
        hint = ("they are tied; " if wanted.superlative else "") + "add a colour, shape or size word"
        raise AmbiguousDescriptionError(
            f"{description!r} fits {len(cands)} objects ({which}); {hint}; "
            f"seen: {seen_list(objects, sizes)}")
    return cands[0]
