"""VideoWriter: MP4 (libx264, yuv420p, even size) with GIF / PNG-sequence fallbacks."""

from __future__ import annotations

import logging

import imageio
import imageio.v3 as iio
import numpy as np
import pytest

from grasp_pipeline.report.video import VideoWriter


def frames(n=12, h=101, w=151):
    for i in range(n):
        f = np.zeros((h, w, 3), np.uint8)
        f[:, : (i + 1) * w // n] = (200, 40, 40)
        yield f


def test_mp4_frame_count_size_and_codec(tmp_path):
    path = tmp_path / "out" / "run.mp4"
    with VideoWriter(path, fps=10) as v:
        for f in frames(12):
            v.append(f)
    assert v.kind == "mp4" and v.path == path and v.frames == 12
    reader = imageio.get_reader(str(path), format="FFMPEG")
    try:
        assert reader.count_frames() == 12
        meta = reader.get_meta_data()
        assert meta["codec"] == "h264"
        assert tuple(meta["size"]) == (152, 102)  # odd 151x101 padded to even for yuv420p
        assert meta["fps"] == pytest.approx(10.0)
        first = reader.get_data(11)
    finally:
        reader.close()
    # the last frame is mostly red-ish (lossy codec: approximate)
    assert first[:, :140, 0].mean() > 150 and first[:, :140, 2].mean() < 90


def test_falls_back_to_gif_with_a_warning_when_ffmpeg_is_missing(tmp_path, monkeypatch, caplog):
    import imageio_ffmpeg

    def no_ffmpeg():
        raise RuntimeError("no ffmpeg binary on this machine")

    monkeypatch.setattr(imageio_ffmpeg, "get_ffmpeg_exe", no_ffmpeg)
    caplog.set_level(logging.WARNING)
    with VideoWriter(tmp_path / "run.mp4", fps=5) as v:
        for f in frames(5, 40, 60):
            v.append(f)
    assert v.kind == "gif" and v.path == tmp_path / "run.gif"
    assert "no ffmpeg binary" in caplog.text and "GIF" in caplog.text
    assert len(iio.imread(v.path, index=None)) == 5


def test_png_sequence_and_frame_normalisation(tmp_path, caplog):
    caplog.set_level(logging.WARNING)
    with VideoWriter(tmp_path / "seq.mp4", fps=5, prefer=("png",)) as v:
        v.append(np.full((20, 30, 3), 0.5))                 # float in [0, 1]
        v.append(np.zeros((20, 30, 4), np.uint8))           # RGBA
        v.append(np.zeros((25, 28), np.uint8))              # grey, other size: fitted
    assert v.kind == "png" and v.path == tmp_path / "seq_frames" and v.frames == 3
    files = sorted(p.name for p in v.path.iterdir())
    assert files == ["frame_00000.png", "frame_00001.png", "frame_00002.png"]
    imgs = [iio.imread(v.path / f) for f in files]
    assert all(im.shape == (20, 30, 3) for im in imgs)
    assert imgs[0][0, 0, 0] == 128
    assert "padding/cropping" in caplog.text


def test_bad_arguments(tmp_path):
    with pytest.raises(ValueError, match="fps"):
        VideoWriter(tmp_path / "a.mp4", fps=0)
    with pytest.raises(ValueError, match="prefer"):
        VideoWriter(tmp_path / "a.mp4", prefer=("avi",))
    with VideoWriter(tmp_path / "a.mp4") as v:
        with pytest.raises(ValueError, match="shape"):
            v.append(np.zeros((4, 4, 2)))
    with pytest.raises(RuntimeError, match="closed"):
        v.append(np.zeros((4, 4, 3)))
