"""Parameter set of the language resolver: ``config/language.yaml``."""

from __future__ import annotations

from dataclasses import dataclass

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
            raise ConfigError(f"LanguageConfig.{field}: {item!r} is not word=meaning")
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

    def validate(self) -> None:
        if len(self.colour_names) != len(self.colour_rgb) or not self.colour_names:
            raise ConfigError("LanguageConfig.colour_names and colour_rgb must be non-empty lists "
                              "of the same length (one RGB triple per name)")
        if any(len(c) != 3 or not all(0.0 <= v <= 1.0 for v in c) for c in self.colour_rgb):
            raise ConfigError("LanguageConfig.colour_rgb: expected [r, g, b] triples in [0, 1]")
        for name in ("shape_cell_m", "shape_top_band_m", "shape_voxel_m", "superlative_tie_m",
                     "colour_chroma_scale", "colour_brightness_weight",
                     "colour_clip_value", "shape_max_points", "colour_samples_per_frame"):
            if not getattr(self, name) > 0:
                raise ConfigError(f"LanguageConfig.{name} = {getattr(self, name)}: expected > 0")
        if not 0.0 <= self.colour_bright_quantile < 1.0:
            raise ConfigError("LanguageConfig.colour_bright_quantile: expected [0, 1)")
        if not 0 < self.size_small_ratio_max < 1 < self.size_large_ratio_min:
            raise ConfigError("LanguageConfig: expected 0 < size_small_ratio_max < 1 < size_large_ratio_min")
        meanings = set(self.shape_map().values()) - set(SHAPES) - {"any"}
        if meanings:
            raise ConfigError(f"LanguageConfig.shape_synonyms: unknown shape(s) {sorted(meanings)}; "
                              f"known: {', '.join(SHAPES)}, any")
        bad = set(self.colour_map().values()) - set(self.colour_names)
        if bad:
            raise ConfigError(f"LanguageConfig.colour_synonyms: {sorted(bad)} not in colour_names")
        bad = set(self.size_map().values()) - set(SIZES) - set(SUPERLATIVES)
        if bad:
            raise ConfigError(f"LanguageConfig.size_synonyms: unknown size word(s) {sorted(bad)}; "
                              f"known: {', '.join(SIZES + SUPERLATIVES)}")

    def colour_map(self) -> dict[str, str]:
        return synonym_map(self.colour_synonyms, "colour_synonyms")

    def shape_map(self) -> dict[str, str]:
        return synonym_map(self.shape_synonyms, "shape_synonyms")

    def size_map(self) -> dict[str, str]:
        return synonym_map(self.size_synonyms, "size_synonyms")
