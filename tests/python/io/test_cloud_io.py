"""Point-cloud files: PCD (PCL reader/writer, all encodings), PLY, NPY, and clear errors."""

from __future__ import annotations

import struct

import numpy as np
import pytest

from grasp_pipeline.exceptions import GraspPipelineError, InputError
from grasp_pipeline.io import Cloud, load_cloud, save_pcd

ENCODINGS = ["ascii", "binary", "binary_compressed"]


def organized_cloud(h=6, w=9, seed=0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    pts = rng.uniform(-2.0, 2.0, size=(h * w, 3)).astype(np.float32)
    pts[[0, 5, 17, h * w - 1]] = np.nan          # invalid pixels, kept in place
    pts[7, 2] = np.nan                            # a partly invalid row
    return pts


@pytest.mark.parametrize("encoding", ENCODINGS)
def test_pcd_round_trip_organized_keeps_nan_rows_and_size(tmp_path, encoding):
    pts = organized_cloud()
    path = tmp_path / f"cloud_{encoding}.pcd"
    save_pcd(path, pts, width=9, height=6, encoding=encoding)
    text = path.read_bytes()[:400].decode("latin-1")
    assert f"DATA {encoding}" in text
    cloud = load_cloud(path)
    assert isinstance(cloud, Cloud)
    assert (cloud.width, cloud.height) == (9, 6)
    assert cloud.organized and cloud.shape_hw == (6, 9)
    assert cloud.source_format == "pcd"
    assert cloud.points.dtype == np.float32 and cloud.points.shape == (54, 3)
    np.testing.assert_array_equal(np.isnan(cloud.points), np.isnan(pts))
    np.testing.assert_array_equal(cloud.points, pts)  # exact, NaN == NaN for assert_array_equal
    assert cloud.num_invalid == 5
    assert cloud.grid().shape == (6, 9, 3)


@pytest.mark.parametrize("encoding", ENCODINGS)
def test_pcd_round_trip_unorganized_and_hw3_input(tmp_path, encoding):
    pts = np.random.default_rng(1).normal(size=(1000, 3)).astype(np.float32)
    save_pcd(tmp_path / "u.pcd", pts, encoding=encoding)
    cloud = load_cloud(tmp_path / "u.pcd")
    assert (cloud.width, cloud.height) == (1000, 1) and not cloud.organized
    np.testing.assert_array_equal(cloud.points, pts)

    grid = organized_cloud(4, 5).reshape(4, 5, 3).astype(np.float64)  # float64 is converted
    save_pcd(tmp_path / "g.pcd", grid, encoding=encoding)
    cloud = load_cloud(tmp_path / "g.pcd")
    assert (cloud.height, cloud.width) == (4, 5)
    np.testing.assert_array_equal(cloud.grid(), grid.astype(np.float32))


def test_pcd_large_organized_binary_compressed(tmp_path):
    # A depth-camera-like 640x480 grid: smooth, so binary_compressed really compresses.
    v, u = np.mgrid[0:480, 0:640].astype(np.float32)
    pts = np.stack([(u - 320) / 600, (v - 240) / 600, np.full_like(u, 0.75)], -1).reshape(-1, 3)
    pts[::7] = np.nan
    save_pcd(tmp_path / "big.pcd", pts, width=640, height=480)
    assert (tmp_path / "big.pcd").stat().st_size < 0.8 * pts.nbytes
    cloud = load_cloud(tmp_path / "big.pcd")
    assert cloud.shape_hw == (480, 640)
    np.testing.assert_array_equal(cloud.points, pts)


def test_pcd_written_by_hand_float64_fields_and_extra_fields(tmp_path):
    path = tmp_path / "hand.pcd"
    path.write_text(
        "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z intensity\n"
        "SIZE 8 8 8 4\nTYPE F F F F\nCOUNT 1 1 1 1\nWIDTH 2\nHEIGHT 2\n"
        "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\nDATA ascii\n"
        "1 2 3 9\n4 5 6.5 9\nnan nan nan 0\n-1 -2 -3 1\n")
    cloud = load_cloud(path)
    assert (cloud.width, cloud.height) == (2, 2)
    np.testing.assert_array_equal(
        cloud.points, np.array([[1, 2, 3], [4, 5, 6.5], [np.nan] * 3, [-1, -2, -3]], np.float32))


def test_ply_ascii_and_binary(tmp_path):
    ascii_ply = tmp_path / "a.ply"
    ascii_ply.write_text(
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property double z\nproperty uchar red\nelement face 1\n"
        "property list uchar int vertex_indices\nend_header\n"
        "0 0 0 255\n1 0 0.5 0\n0 1 0.25 10\n3 0 1 2\n")
    cloud = load_cloud(ascii_ply)
    assert cloud.source_format == "ply" and (cloud.width, cloud.height) == (3, 1)
    np.testing.assert_array_equal(cloud.points, [[0, 0, 0], [1, 0, 0.5], [0, 1, 0.25]])

    pts = np.random.default_rng(2).normal(size=(50, 3)).astype(np.float32)
    header = ("ply\nformat binary_little_endian 1.0\nelement vertex 50\nproperty float x\n"
              "property float y\nproperty float z\nend_header\n").encode()
    bin_ply = tmp_path / "b.ply"
    bin_ply.write_bytes(header + b"".join(struct.pack("<3f", *p) for p in pts))
    np.testing.assert_array_equal(load_cloud(bin_ply).points, pts)


def test_npy_unorganized_and_organized(tmp_path):
    pts = np.random.default_rng(4).normal(size=(20, 3))           # float64
    np.save(tmp_path / "u.npy", pts)
    cloud = load_cloud(tmp_path / "u.npy")
    assert cloud.source_format == "npy" and (cloud.width, cloud.height) == (20, 1)
    assert cloud.points.dtype == np.float32
    np.testing.assert_allclose(cloud.points, pts, rtol=1e-6)

    grid = organized_cloud(3, 7).reshape(3, 7, 3)
    np.save(tmp_path / "o.npy", grid)
    cloud = load_cloud(str(tmp_path / "o.npy"))
    assert (cloud.height, cloud.width) == (3, 7)
    np.testing.assert_array_equal(cloud.grid(), grid)


# ---- errors: always an InputError naming the file and the problem -------------------------
def _expect_error(path, *needles):
    with pytest.raises(InputError) as info:
        load_cloud(path)
    msg = str(info.value)
    for needle in needles:
        assert needle in msg, msg
    assert isinstance(info.value, GraspPipelineError)
    return msg


def test_missing_files(tmp_path):
    for ext in (".pcd", ".ply", ".npy"):
        _expect_error(tmp_path / f"nope{ext}", "not found", f"nope{ext}")


def test_unsupported_extension(tmp_path):
    (tmp_path / "c.xyz").write_text("1 2 3\n")
    _expect_error(tmp_path / "c.xyz", "unsupported", ".pcd", ".ply", ".npy")
    _expect_error(tmp_path / "noext", "unsupported")


def test_garbage_and_truncated_pcd(tmp_path):
    (tmp_path / "garbage.pcd").write_bytes(b"hello\x00\x01 this is not a point cloud" * 20)
    _expect_error(tmp_path / "garbage.pcd", "garbage.pcd", "not a readable PCD")
    (tmp_path / "empty.pcd").write_bytes(b"")
    _expect_error(tmp_path / "empty.pcd", "not a readable PCD")

    pts = organized_cloud()
    for enc in ("binary", "binary_compressed"):
        save_pcd(tmp_path / "full.pcd", pts, 9, 6, encoding=enc)
        data = (tmp_path / "full.pcd").read_bytes()
        start = data.index(b"DATA") + len(f"DATA {enc}\n")
        (tmp_path / "cut.pcd").write_bytes(data[:start + 20])
        _expect_error(tmp_path / "cut.pcd", "truncated")
        (tmp_path / "cut.pcd").write_bytes(data[:start - 5])
        _expect_error(tmp_path / "cut.pcd", "not a readable PCD")


def test_pcd_without_xyz_fields(tmp_path):
    path = tmp_path / "noxyz.pcd"
    path.write_text("VERSION 0.7\nFIELDS a b c\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\n"
                    "HEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3\n")
    _expect_error(path, "no 'x' field", "a b c")


def test_bad_ply(tmp_path):
    (tmp_path / "g.ply").write_bytes(b"\x00\x01\x02 not a ply")
    _expect_error(tmp_path / "g.ply", "not a readable PLY")
    (tmp_path / "n.ply").write_text("ply\nformat ascii 1.0\nelement vertex 1\nproperty float u\n"
                                    "property float v\nend_header\n1 2\n")
    _expect_error(tmp_path / "n.ply", "no 'x' field")


def test_bad_npy(tmp_path):
    np.save(tmp_path / "two.npy", np.zeros((5, 2), np.float32))
    _expect_error(tmp_path / "two.npy", "(N, 3) or (H, W, 3)", "(5, 2)")
    np.save(tmp_path / "int.npy", np.zeros((5, 3), np.int32))
    _expect_error(tmp_path / "int.npy", "float32/float64", "int32")
    (tmp_path / "junk.npy").write_bytes(b"junk")
    _expect_error(tmp_path / "junk.npy", "not a readable .npy")


def test_save_pcd_errors(tmp_path):
    pts = organized_cloud()
    with pytest.raises(InputError, match="width x height"):
        save_pcd(tmp_path / "x.pcd", pts, width=5, height=5)
    with pytest.raises(InputError, match="encoding"):
        save_pcd(tmp_path / "x.pcd", pts, encoding="lzma")
    with pytest.raises(InputError, match=r"\(N, 3\)"):
        save_pcd(tmp_path / "x.pcd", pts[:, :2])
    with pytest.raises(InputError, match="could not write"):
        save_pcd(tmp_path / "no_such_dir" / "x.pcd", pts)
