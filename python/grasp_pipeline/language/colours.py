"""Colour names from RGB: the nearest named reference colour, shading-tolerant.

Shading (the light's angle, the distance, a renderer's lighting model) scales a surface's
RGB far more than it changes the ratios between its channels, so a colour is compared in two
parts: its **chromaticity** ``(r, g) = (R, G) / (R + G + B)`` (unchanged when the colour is
scaled) and its **brightness** ``V = max(R, G, B)``. The distance to a reference is
``|chroma - chroma_ref| / colour_chroma_scale + colour_brightness_weight · |ln(V / V_ref)|``;
the name is the reference of ``config/language.yaml`` at the smallest distance. A hue far off
costs a lot; a brightness off by a factor e costs only ``colour_brightness_weight`` — which
is why the achromatic names (white, silver, grey) are told apart by brightness alone and are
the least reliable under changing light. Exact reference colours (e.g. the built-in objects'
RGBA) get their own name.

An object's colour (:func:`object_colour`): its points' colours without the clipped ones
(a channel at ``colour_clip_value`` or above — a highlight no longer has the surface's
ratios), then the per-channel median of the brighter part (``max(R, G, B)`` at least the
``colour_bright_quantile`` of them): the median ignores outliers (edges showing the table),
and the brighter part is lit most directly, nearest the object's own brightness.
"""

from __future__ import annotations

import numpy as np

from .config import LanguageConfig

_TINY = 1e-6


def as_unit_rgb(rgb) -> np.ndarray:
    """sRGB as floats in 0..1 (uint8 arrays and numbers above 1 are read as 0..255)."""
    a = np.asarray(rgb)
    if a.dtype == np.uint8:
        return a.astype(float) / 255.0
    a = a.astype(float)
    if a.size and np.nanmax(a) > 1.0 + 1e-9:
        a = a / 255.0
    return np.clip(a, 0.0, 1.0)


def chroma_value(rgb) -> tuple[np.ndarray, np.ndarray]:
    """((..., 2) chromaticity (r, g), (...,) brightness V) of sRGB in 0..1."""
    c = as_unit_rgb(rgb)[..., :3]
    total = np.maximum(c.sum(axis=-1, keepdims=True), _TINY)
    chroma = np.where(total > 3 * _TINY, c[..., :2] / total, 1.0 / 3.0)
    return chroma, c.max(axis=-1)


def colour_distances(rgb, config: LanguageConfig | None = None) -> dict[str, float]:
    """Distance from ``rgb`` to every named reference colour (see the module doc)."""
    cfg = config or LanguageConfig()
    chroma, value = chroma_value(np.asarray(rgb, dtype=float)[:3] if np.asarray(rgb).dtype != np.uint8
                                 else rgb)
    ref_chroma, ref_value = chroma_value(np.array(cfg.colour_rgb, dtype=float))
    d = (np.linalg.norm(ref_chroma - chroma, axis=1) / cfg.colour_chroma_scale
         + cfg.colour_brightness_weight
         * np.abs(np.log(max(float(value), _TINY) / np.maximum(ref_value, _TINY))))
    return dict(zip(cfg.colour_names, d.tolist()))


def colour_name(rgb, config: LanguageConfig | None = None) -> str:
    """The name of one colour: ``colour_name((0.85, 0.15, 0.13)) == "red"``. Takes an sRGB
    triple in 0..1 (e.g. an object's RGBA — the alpha is ignored) or in 0..255."""
    d = colour_distances(np.asarray(rgb)[:3], config)
    return min(d, key=d.get)


def object_colour(samples_rgb: np.ndarray, config: LanguageConfig | None = None) -> np.ndarray:
    """(3,) sRGB 0..1 of an object from (N, 3) samples of its points' colours (see the module
    doc); NaN when there are no samples."""
    cfg = config or LanguageConfig()
    c = as_unit_rgb(samples_rgb).reshape(-1, 3)
    unclipped = c[c.max(axis=1) < cfg.colour_clip_value]
    if len(unclipped):
        c = unclipped
    if len(c) == 0:
        return np.full(3, np.nan)
    value = c.max(axis=1)
    bright = c[value >= np.quantile(value, cfg.colour_bright_quantile)]
    return np.median(bright, axis=0)
