"""Cloud files whose headers declare more points than allowed, or more data than the file holds,
are refused from the header alone: at once and without allocating for the claimed count."""

from __future__ import annotations

import resource
import struct
import time

import numpy as np
import pytest

from grasp_pipeline.exceptions import InputError
from grasp_pipeline.io.cloud_headers import MAX_CLOUD_POINTS
from grasp_pipeline.io.cloud_io import load_cloud


def _refused(path) -> str:
    rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    t0 = time.perf_counter()
    with pytest.raises(InputError) as info:
        load_cloud(path)
    assert time.perf_counter() - t0 < 2.0
    assert resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - rss0 < 200_000  # kB: nothing claimed was allocated
    assert str(path) in str(info.value)
    return str(info.value)


def _ply(tmp_path, n, body=b"", fmt="binary_little_endian", faces=None):
    head = (f"ply\nformat {fmt} 1.0\nelement vertex {n}\nproperty float x\nproperty float y\n"
            "property float z\n")
    if faces is not None:
        head += f"element face {faces}\nproperty list uchar int vertex_indices\n"
    path = tmp_path / "c.ply"
    path.write_bytes((head + "end_header\n").encode() + body)
    return path


def test_a_ply_claiming_a_billion_points_is_refused(tmp_path):
    msg = _refused(_ply(tmp_path, 10**9, np.zeros((10, 3), np.float32).tobytes()))
    assert "declares 1000000000 vertices" in msg and str(MAX_CLOUD_POINTS) in msg


def test_a_ply_claiming_more_than_it_holds_is_refused(tmp_path):
    msg = _refused(_ply(tmp_path, 1_000_000, np.zeros((10, 3), np.float32).tobytes()))
    assert "12000000 bytes at least" in msg and "holds 120 bytes" in msg
    msg = _refused(_ply(tmp_path, 10, np.zeros((10, 3), np.float32).tobytes(), faces=10**7))
    assert "10000010 element instances" in msg


def test_a_pcd_claiming_too_much_is_refused(tmp_path):
    head = ("VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH {n}\nHEIGHT 1\n"
            "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS {n}\nDATA {enc}\n")
    compressed = tmp_path / "c.pcd"
    compressed.write_bytes(head.format(n=300_000_000, enc="binary_compressed").encode()
                           + struct.pack("<II", 16, 3_600_000_000 % 2**32) + bytes(16))
    assert "declares 300000000 points" in _refused(compressed)
    binary = tmp_path / "b.pcd"
    binary.write_bytes(head.format(n=5_000_000, enc="binary").encode() + bytes(120))
    assert "60000000 bytes at least" in _refused(binary)


def test_an_npy_claiming_too_much_is_refused(tmp_path):
    path = tmp_path / "c.npy"
    with path.open("wb") as fh:
        np.lib.format.write_array_header_1_0(fh, {"descr": "<f4", "fortran_order": False, "shape": (10**9, 3)})
        fh.write(bytes(120))
    assert "declares 1000000000 points" in _refused(path)
    with path.open("wb") as fh:
        np.lib.format.write_array_header_1_0(fh, {"descr": "<f4", "fortran_order": False, "shape": (1000, 3)})
        fh.write(bytes(120))
    assert "12000 bytes at least" in _refused(path)


def test_honest_headers_still_load(tmp_path):
    pts = np.arange(30, dtype=np.float32).reshape(10, 3)
    assert np.array_equal(load_cloud(_ply(tmp_path, 10, pts.tobytes())).points, pts)
    np.save(tmp_path / "c.npy", pts)
    assert np.array_equal(load_cloud(tmp_path / "c.npy").points, pts)
