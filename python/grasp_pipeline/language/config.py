"""Parameter set of the language resolver: ``config/language.yaml``."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, Mapping

from ..config_ranges import (FRACTION, POSITIVE_FRACTION, Range, check_ranges, count, length_m,
                             require, step_m)
from ..exceptions import ConfigError

#: The shape classes the resolver names (``any`` is the word "object": every shape).
SHAPES = ("box", "cylinder", "mug", "bottle", "other")
#: Words that pick the extreme object among those that fit the rest of the description.
SUPERLATIVES = ("tallest", "nearest", "smallest", "largest")
#: Gradable size words, relative to the objects seen.
SIZES = ("small", "large")


def synonym_map(pairs: tuple[str, ...], field: str) -> dict[str, str]:
    """``("gray=grey", ...)`` → ``{"gray": "grey"}``."""
    out = {}
    for item in pairs:
        word, sep, meaning = item.partition("=")
        if not sep or not word.strip() or not meaning.strip():
            raise ConfigError(f"language.{field}: {item!r} is not word=meaning")
        out[word.strip().lower()] = meaning.strip().lower()
    return out


@dataclass(frozen=True)
class LanguageConfig:
    """Vocabulary and naming rules (see the comments of ``config/language.yaml``)."""

    colour_names: tuple[str, ...] = ("red", "green", "blue", "yellow", "orange", "purple", "pink",
                                     "cyan", "white", "grey", "brown", "silver", "black")
    colour_rgb: tuple[tuple[float, ...], ...] = (
        (0.85, 0.15, 0.13), (0.20, 0.65, 0.25), (0.15, 0.35, 0.85), (0.95, 0.85, 0.20),
        (0.95, 0.55, 0.10), (0.55, 0.25, 0.70), (0.95, 0.55, 0.70), (0.20, 0.75, 0.80),
        (0.92, 0.92, 0.90), (0.55, 0.55, 0.55), (0.55, 0.35, 0.20), (0.76, 0.77, 0.80),
        (0.05, 0.05, 0.05))
    colour_synonyms: tuple[str, ...] = ("gray=grey", "violet=purple", "turquoise=cyan")
    colour_chroma_scale: float = 0.1
    colour_brightness_weight: float = 0.3
    colour_clip_value: float = 0.98
    colour_bright_quantile: float = 0.5
    colour_samples_per_frame: int = 400
    shape_synonyms: tuple[str, ...] = ("block=box", "cube=box", "cuboid=box", "can=cylinder",
                                       "cup=mug", "object=any", "thing=any", "item=any", "one=any")
    shape_cell_m: float = 0.004
    shape_top_band_m: float = 0.008
    shape_rect_fill_min: float = 0.88
    shape_round_fill_max: float = 0.86
    shape_round_aspect_min: float = 0.93
    shape_round_corner_max: float = 1.15
    shape_flat_top_min: float = 0.6
    shape_hollow_drop_min: float = 0.3
    shape_mug_height_ratio_min: float = 0.8
    shape_bottle_top_max: float = 0.5
    shape_bottle_height_ratio_min: float = 1.5
    shape_max_points: int = 20000
    shape_voxel_m: float = 0.002
    size_small_ratio_max: float = 0.6
    size_large_ratio_min: float = 1.6
    size_synonyms: tuple[str, ...] = ("little=small", "big=large", "closest=nearest",
                                      "highest=tallest", "biggest=largest")
    superlative_tie_m: float = 0.005
    superlative_tie_volume_ratio: float = 0.1
    filler_words: tuple[str, ...] = ("the", "a", "an")

    RANGES: ClassVar[Mapping[str, Range]] = {
        "colour_rgb": FRACTION,
        "colour_chroma_scale": POSITIVE_FRACTION,
        "colour_brightness_weight": Range(0.0, 10.0, lo_open=True),
        "colour_clip_value": POSITIVE_FRACTION,
        "colour_bright_quantile": Range(0.0, 1.0, hi_open=True),
        "colour_samples_per_frame": count(1, 100_000),
        "shape_cell_m": step_m(),
        "shape_top_band_m": length_m(0.1),
        "shape_rect_fill_min": FRACTION,
        "shape_round_fill_max": FRACTION,
        "shape_round_aspect_min": FRACTION,
        "shape_round_corner_max": Range(1.0, 10.0),
        "shape_flat_top_min": FRACTION,
        "shape_hollow_drop_min": FRACTION,
        "shape_mug_height_ratio_min": Range(0.0, 100.0),
        "shape_bottle_top_max": FRACTION,
        "shape_bottle_height_ratio_min": Range(0.0, 100.0),
        "shape_max_points": count(1, 10_000_000),
        "shape_voxel_m": step_m(),
        "size_small_ratio_max": Range(0.0, 1.0, lo_open=True, hi_open=True),
        "size_large_ratio_min": Range(1.0, 100.0, lo_open=True),
        "superlative_tie_m": length_m(0.1),
        "superlative_tie_volume_ratio": FRACTION,
    }

    def validate(self) -> None:
        check_ranges(self, "language")
        if len(self.colour_names) != len(self.colour_rgb) or not self.colour_names:
            raise ConfigError("language.colour_names and colour_rgb must be non-empty lists "
                              "of the same length (one RGB triple per name)")
        require(all(len(c) == 3 for c in self.colour_rgb), "language", "colour_rgb",
                self.colour_rgb, "[r, g, b] triples in [0, 1]")
        meanings = set(self.shape_map().values()) - set(SHAPES) - {"any"}
        if meanings:
            raise ConfigError(f"language.shape_synonyms: unknown shape(s) {sorted(meanings)}; "
                              f"known: {', '.join(SHAPES)}, any")
        bad = set(self.colour_map().values()) - set(self.colour_names)
        if bad:
            raise ConfigError(f"language.colour_synonyms: {sorted(bad)} not in colour_names")
        bad = set(self.size_map().values()) - set(SIZES) - set(SUPERLATIVES)
        if bad:
            raise ConfigError(f"language.size_synonyms: unknown size word(s) {sorted(bad)}; "
                              f"known: {', '.join(SIZES + SUPERLATIVES)}")

    def colour_map(self) -> dict[str, str]:
        return synonym_map(self.colour_synonyms, "colour_synonyms")

    def shape_map(self) -> dict[str, str]:
        return synonym_map(self.shape_synonyms, "shape_synonyms")

    def size_map(self) -> dict[str, str]:
        return synonym_map(self.size_synonyms, "size_synonyms")
