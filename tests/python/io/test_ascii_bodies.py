"""ASCII PCD / PLY bodies are checked line by line before PCL reads them.

Regression: PCL's ASCII PCD reader turned a non-number (``0.1 abc 0.3``) into 0 and
loaded the file without complaint (exit 0 from ``perceive``); a line with too few/many
values became a point of zeros; extra data lines were ignored; ASCII PLY read ``abc`` as
NaN and reported short/long lines as "problem parsing header". Now every such file is an
InputError naming the file, the line number and the field; NaN/Inf literals stay legal.
"""

from __future__ import annotations

import numpy as np
import pytest

from grasp_pipeline.exceptions import InputError
from grasp_pipeline.io import load_cloud, save_pcd

PCD_HEADER = ("# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
              "WIDTH {n}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {n}\nDATA ascii\n")
FIRST_DATA_LINE = 12  # the header above has 11 lines
PLY_HEADER = ("ply\nformat ascii 1.0\nelement vertex {n}\nproperty float x\nproperty float y\n"
              "property float z\nend_header\n")
FIRST_PLY_LINE = 8


def write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return path


def load_error(path) -> str:
    with pytest.raises(InputError) as info:
        load_cloud(path)
    return str(info.value)


@pytest.mark.parametrize("body, line, words", [
    ("0.1 0.2 0.3\n0.1 abc 0.3\n1 2 3\n", 2, ["field 'y'", "'abc' is not a number"]),
    ("0.1 0.2 0.3\n1 2 3\n4 5 6ab\n", 3, ["field 'z'", "'6ab'"]),
    ("0x10 0.2 0.3\n1 2 3\n4 5 6\n", 1, ["field 'x'", "'0x10'"]),
    ("0.1 0.2 0.3\n0.1 0.3\n1 2 3\n", 2, ["expected 3 values", "got 2"]),
    ("0.1 0.2 0.3\n0.1 0.3 4 5\n1 2 3\n", 2, ["expected 3 values", "got 4"]),
    ("0.1 0.2 0.3\n   \n1 2 3\n", 2, ["got 0"]),  # PCL reads a blank line as a point of zeros
    ("0.1 0.2 0.3\n1 2 3\n4 5 6\n7 8 9\n", 4, ["more data lines than POINTS = 3"]),
])
def test_pcd_ascii_errors_name_the_line_and_the_field(tmp_path, body, line, words):
    assert_error_names(write(tmp_path, "bad.pcd", PCD_HEADER.format(n=3) + body),
                       FIRST_DATA_LINE + line - 1, words)


def assert_error_names(path, file_line: int, words) -> None:
    """Loading ``path`` fails with a message naming the file, the line and ``words``."""
    msg = load_error(path)
    assert str(path) in msg and f"line {file_line}" in msg, msg
    for w in words:
        assert w in msg, msg


def test_pcd_ascii_too_few_lines_and_integer_fields(tmp_path):
    msg = load_error(write(tmp_path, "short.pcd", PCD_HEADER.format(n=3) + "0.1 0.2 0.3\n1 2 3\n"))
    assert "only 2 data lines, but POINTS = 3" in msg
    header = ("VERSION 0.7\nFIELDS x y z label\nSIZE 4 4 4 2\nTYPE F F F U\nCOUNT 1 1 1 1\n"
              "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n")
    for value, why in [("4.5", "not an integer"), ("-1", "negative"), ("70000", "out of range")]:
        msg = load_error(write(tmp_path, "u.pcd", header + f"1 2 3 {value}\n"))
        assert "line 10" in msg and "field 'label'" in msg and why in msg, msg
    assert load_cloud(write(tmp_path, "ok.pcd", header + "1 2 3 65535\n")).points.shape == (1, 3)


def test_pcd_ascii_nan_inf_counts_and_empty_lines_are_legal(tmp_path):
    body = "nan NaN 0.3\ninf -Inf +3\n\n1e39 -2.5E-3 .5\n"
    cloud = load_cloud(write(tmp_path, "ok.pcd", PCD_HEADER.format(n=3) + body))
    pts = cloud.points
    assert np.isnan(pts[0, :2]).all() and pts[0, 2] == np.float32(0.3)
    assert pts[1, 0] == np.inf and pts[1, 1] == -np.inf and pts[2, 0] == np.inf  # 1e39 > float max
    np.testing.assert_array_equal(pts[2, 1:], np.float32([-2.5e-3, 0.5]))
    header = ("VERSION 0.7\nFIELDS x y z normal\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 3\n"
              "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n")
    assert load_cloud(write(tmp_path, "c.pcd", header + "1 2 3 0 0 1\n")).points.tolist() == [[1, 2, 3]]
    msg = load_error(write(tmp_path, "c2.pcd", header + "1 2 3 0 x 1\n"))
    assert "field 'normal[1]' (column 5)" in msg


def test_saved_ascii_pcd_round_trips(tmp_path):
    pts = np.random.default_rng(3).normal(size=(500, 3)).astype(np.float32)
    pts[7] = np.nan
    save_pcd(tmp_path / "a.pcd", pts, encoding="ascii")
    np.testing.assert_array_equal(load_cloud(tmp_path / "a.pcd").points, pts)


@pytest.mark.parametrize("body, line, words", [
    ("0.1 0.2 0.3\n0.1 abc 0.3\n1 2 3\n", 2, ["property 'y' of element 'vertex'", "'abc' is not a number"]),
    ("0.1 0.2 0.3\n0.1 0.3\n1 2 3\n", 2, ["too few values", "property 'z' is missing"]),
    ("0.1 0.2 0.3\n0.1 0.3 4 5\n1 2 3\n", 2, ["too many values", "expected 3, got 4"]),
    ("0.1 0.2 0.3\n1 2 3\n4 5 6\n7 8 9\n", 4, ["data after the last element"]),
])
def test_ply_ascii_errors_name_the_line_and_the_property(tmp_path, body, line, words):
    assert_error_names(write(tmp_path, "bad.ply", PLY_HEADER.format(n=3) + body),
                       FIRST_PLY_LINE + line - 1, words)


def test_ply_ascii_short_file_lists_and_nan(tmp_path):
    msg = load_error(write(tmp_path, "s.ply", PLY_HEADER.format(n=3) + "0 0 0\n1 1 1\n"))
    assert "only 2 of the 3 'vertex' lines" in msg
    faces = ("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
             "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
             "nan 0 0\ninf 1 0\n0 1 0\n")
    cloud = load_cloud(write(tmp_path, "f.ply", faces + "3 0 1 2\n"))
    assert np.isnan(cloud.points[0, 0]) and cloud.points[1, 0] == np.inf
    msg = load_error(write(tmp_path, "f2.ply", faces + "3 0 1\n"))
    assert "line 13" in msg and "element 'face'" in msg and "too few values" in msg
    msg = load_error(write(tmp_path, "f3.ply", faces + "3 0 1.5 2\n"))
    assert "property 'vertex_indices'" in msg and "not an integer" in msg
