"""A short English description → the attributes it asks for.

Grammar (ours): any order of at most one colour word, one shape word, one size word
(small/large) and one superlative (tallest/nearest/smallest/largest), plus filler words
("the", "a", "an"); synonyms from ``config/language.yaml`` ("can" = cylinder, "cup" = mug,
"object" = any shape, "big" = large, "closest" = nearest). Case and punctuation are ignored.
Any other word is refused with the vocabulary; so is a description that names nothing or two
values of one attribute.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Optional

from .config import SHAPES, SIZES, SUPERLATIVES, LanguageConfig
from .exceptions import DescriptionError, UnknownWordError


@dataclass(frozen=True)
class Wanted:
    """What a description asks for (None: not constrained)."""

    colour: Optional[str] = None
    shape: Optional[str] = None        # a shape class; None also for "object"
    size: Optional[str] = None         # small, large
    superlative: Optional[str] = None  # tallest, nearest, smallest, largest

    def phrase(self) -> str:
        """The words again, normalised: "tallest red box"."""
        words = [self.superlative, self.size, self.colour, self.shape or "object"]
        return " ".join(w for w in words if w)


def vocabulary(config: LanguageConfig) -> dict[str, dict[str, str]]:
    """attribute → {word: meaning} of every word the resolver understands."""
    return {
        "colour": {**{c: c for c in config.colour_names}, **config.colour_map()},
        "shape": {**{s: s for s in SHAPES if s != "other"}, **config.shape_map()},
        "size": {**{s: s for s in SIZES + SUPERLATIVES}, **config.size_map()},
    }


def vocabulary_text(config: LanguageConfig) -> str:
    v = vocabulary(config)
    return "; ".join(f"{k}: {', '.join(sorted(words))}" for k, words in v.items())


def parse(description: str, config: LanguageConfig | None = None) -> Wanted:
    """The attributes ``description`` asks for (see the module doc)."""
    cfg = config or LanguageConfig()
    words = [w for w in re.split(r"[\s,.;:!?]+", str(description).lower()) if w]
    vocab = vocabulary(cfg)
    fillers = {w.lower() for w in cfg.filler_words}
    unknown = [w for w in words if w not in fillers and not any(w in v for v in vocab.values())]
    if unknown:
        raise UnknownWordError(f"{description!r}: unknown word(s) {', '.join(repr(w) for w in unknown)}; "
                               f"known words: {vocabulary_text(cfg)}")
    found: dict[str, list[str]] = {"colour": [], "shape": [], "size": []}
    for w in words:
        for attr, v in vocab.items():
            if w in v:
                found[attr].append(v[w])
    sizes = found.pop("size")
    found["size"] = [s for s in sizes if s in SIZES]
    found["superlative"] = [s for s in sizes if s in SUPERLATIVES]
    for attr, values in found.items():
        if len(set(values)) > 1:
            raise DescriptionError(f"{description!r} names more than one {attr} "
                                   f"({', '.join(values)}); give one")
    if not any(found.values()):
        raise DescriptionError(f"{description!r} names no object; describe it with a colour, shape "
                               f"or size word, e.g. \"the red mug\" ({vocabulary_text(cfg)})")
    shape = found["shape"][0] if found["shape"] else None
    return Wanted(colour=(found["colour"] or [None])[0], shape=None if shape == "any" else shape,
                  size=(found["size"] or [None])[0], superlative=(found["superlative"] or [None])[0])
