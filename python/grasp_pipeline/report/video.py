"""Write a run's frames to a video: MP4 (H.264) where an encoder exists, else GIF, else PNGs.

``VideoWriter(path, fps)`` is a context manager; ``append(frame)`` takes an (H, W, 3) or
(H, W, 4) uint8 image (float images in [0, 1] are converted; RGBA drops alpha; grey (H, W)
is expanded). Output formats, tried in the order of ``prefer``:

- ``"mp4"``: imageio's FFMPEG plugin with the ffmpeg binary bundled in ``imageio-ffmpeg``,
  codec ``libx264``, pixel format ``yuv420p`` (plays everywhere). yuv420p needs even sizes,
  so frames are padded by one edge-replicated row/column where odd (``macro_block_size=1``:
  imageio does not rescale). The output file is ``path``.
- ``"gif"``: imageio's Pillow plugin, ``path`` with the suffix ``.gif``.
- ``"png"``: a numbered PNG sequence in the directory ``<path without suffix>_frames/``.

Falling back logs a warning that says why. Every frame after the first is fitted to the
first frame's size (padded with edge pixels / cropped, warning once): a video has one size.
After ``close()`` (or the ``with`` block), ``writer.path`` is the file/directory written,
``writer.kind`` the format used and ``writer.frames`` the number of frames.
"""

from __future__ import annotations

import logging
import os
from pathlib import Path
from typing import Sequence

import numpy as np

log = logging.getLogger("grasp_pipeline.report.video")

FORMATS = ("mp4", "gif", "png")


def _as_rgb_uint8(frame) -> np.ndarray:
    a = np.asarray(frame)
    if a.ndim == 2:
        a = np.repeat(a[:, :, None], 3, axis=2)
    if a.ndim != 3 or a.shape[2] not in (3, 4):
        raise ValueError(f"frame: expected shape (H, W, 3), (H, W, 4) or (H, W), got {a.shape}")
    a = a[:, :, :3]
    if a.dtype != np.uint8:
        if np.issubdtype(a.dtype, np.floating):
            a = np.clip(np.nan_to_num(a), 0.0, 1.0) * 255.0 + 0.5
        a = np.clip(a, 0, 255).astype(np.uint8)
    return np.ascontiguousarray(a)


def _fit(frame: np.ndarray, h: int, w: int) -> np.ndarray:
    """Crop / edge-pad ``frame`` to (h, w)."""
    f = frame[:h, :w]
    ph, pw = h - f.shape[0], w - f.shape[1]
    if ph or pw:
        f = np.pad(f, ((0, ph), (0, pw), (0, 0)), mode="edge")
    return f


class VideoWriter:
    """Context manager writing frames to MP4 / GIF / PNG sequence (see module docstring)."""

    def __init__(self, path: str | os.PathLike, fps: float = 10.0,
                 prefer: Sequence[str] = FORMATS, quality: int = 8) -> None:
        if fps <= 0:
            raise ValueError(f"fps must be > 0, got {fps}")
        unknown = [k for k in prefer if k not in FORMATS]
        if unknown or not prefer:
            raise ValueError(f"prefer: formats must be among {FORMATS}, got {tuple(prefer)}")
        self.requested = Path(os.fspath(path))
        self.fps = float(fps)
        self.prefer = tuple(prefer)
        self.quality = quality
        self.path: Path | None = None
        self.kind: str | None = None
        self.frames = 0
        self._writer = None
        self._size: tuple[int, int] | None = None  # (h, w) of the output
        self._warned_size = False
        self._closed = False

    # ---- context manager --------------------------------------------------------------
    def __enter__(self) -> "VideoWriter":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    # ---- opening --------------------------------------------------------------------
    def _open(self, h: int, w: int) -> None:
        self.requested.parent.mkdir(parents=True, exist_ok=True)
        reasons = []
        for kind in self.prefer:
            try:
                self._open_kind(kind)
            except Exception as exc:  # no encoder / plugin: try the next format
                reasons.append(f"{kind}: {exc}")
                continue
            self.kind = kind
            if reasons:
                log.warning("video: %s not available (%s); writing %s to %s", self.prefer[0],
                            "; ".join(reasons), kind.upper(), self.path)
            return
        raise RuntimeError("no video output possible: " + "; ".join(reasons))

    def _open_kind(self, kind: str) -> None:
        import imageio

        if kind == "mp4":
            import imageio_ffmpeg

            imageio_ffmpeg.get_ffmpeg_exe()  # raises when no ffmpeg binary is available
            path = self.requested if self.requested.suffix else self.requested.with_suffix(".mp4")
            self._writer = imageio.get_writer(
                str(path), format="FFMPEG", mode="I", fps=self.fps, codec="libx264",
                pixelformat="yuv420p", macro_block_size=1, quality=self.quality,
                ffmpeg_log_level="error")
        elif kind == "gif":
            path = self.requested.with_suffix(".gif")
            self._writer = imageio.get_writer(str(path), format="GIF", mode="I",
                                              duration=1000.0 / self.fps, loop=0)
        else:
            path = self.requested.parent / (self.requested.stem + "_frames")
            path.mkdir(parents=True, exist_ok=True)
            self._writer = None
        self.path = path

    # ---- writing --------------------------------------------------------------------
    def append(self, frame) -> None:
        if self._closed:
            raise RuntimeError("VideoWriter is closed")
        f = _as_rgb_uint8(frame)
        if self._size is None:
            h, w = f.shape[:2]
            self._size = (h + (h % 2), w + (w % 2))  # yuv420p: even sizes
            self._open(*self._size)
        h, w = self._size
        if f.shape[:2] != (h, w):
            if (f.shape[0] + f.shape[0] % 2, f.shape[1] + f.shape[1] % 2) != (h, w) and not self._warned_size:
                log.warning("video: frame %d is %dx%d, the video is %dx%d; padding/cropping",
                            self.frames, f.shape[1], f.shape[0], w, h)
                self._warned_size = True
            f = _fit(f, h, w)
        if self.kind == "png":
            import imageio

            imageio.imwrite(str(self.path / f"frame_{self.frames:05d}.png"), f)
        else:
            self._writer.append_data(f)
        self.frames += 1

    def close(self) -> None:
        if self._closed:
            return
        self._closed = True
        if self._writer is not None:
            self._writer.close()
            self._writer = None
        if self.frames == 0:
            log.warning("video: no frames were written to %s", self.requested)
        else:
            log.info("video: %d frames (%s) -> %s", self.frames, self.kind, self.path)
