"""The C++ per-pixel passes of the simulated camera (``_core.mask_invalid_and_grazing``,
``_core.depth_to_world_points``) refuse bad arrays with a clear error instead of reading out
of bounds; that their results equal the numpy formulation bit for bit is tested on whole
frames in test_sim_camera.py."""

import numpy as np
import pytest

from grasp_pipeline import _core

H, W = 4, 5


def _args():
    z = np.full((H, W), 0.5, dtype=np.float32)
    invalid = np.zeros((H, W), dtype=bool)
    x = np.linspace(-0.5, 0.5, W, dtype=np.float32)
    y = np.linspace(-0.4, 0.4, H, dtype=np.float32)
    rn2 = (1 + x[None, :] ** 2 + y[:, None] ** 2).astype(np.float32)
    return z, invalid, x, y, rn2


def test_a_flat_image_facing_the_camera_keeps_every_pixel_and_back_projects():
    z, invalid, x, y, rn2 = _args()
    invalid[1, 2] = True
    _core.mask_invalid_and_grazing(z, invalid, x, y, rn2, 100.0, 100.0, 0.03)
    assert np.isnan(z[1, 2]) and invalid.sum() == 1
    pts = _core.depth_to_world_points(z, invalid, x, y, np.eye(3, dtype=np.float32),
                                      np.array([0, 0, 1], dtype=np.float32))
    assert pts.shape == (H * W, 3) and pts.dtype == np.float32
    assert np.isnan(pts[1 * W + 2]).all()
    assert pts[0].tolist() == pytest.approx([x[0] * 0.5, y[0] * 0.5, 1.5])


@pytest.mark.parametrize("bad, error, words", [
    ({"depth": np.zeros((H, W))}, TypeError, "depth: expected dtype float32"),
    ({"depth": np.zeros((H, W + 1), dtype=np.float32)}, ValueError, "depth: expected shape"),
    ({"invalid": np.zeros((H, W), dtype=np.uint8)}, TypeError, "invalid: expected dtype bool"),
    ({"depth": np.zeros((W, H), dtype=np.float32).T}, ValueError, "C-ordered"),
    ({"ray_norm2": np.zeros((H, W - 1), dtype=np.float32)}, ValueError, "ray_norm2: expected shape"),
    ({"x": [0.0] * W}, TypeError, "x: expected a numpy array"),
])
def test_bad_arrays_are_refused_by_name(bad, error, words):
    z, invalid, x, y, rn2 = _args()
    args = {"depth": z, "invalid": invalid, "x": x, "y": y, "ray_norm2": rn2, **bad}
    with pytest.raises(error, match=words):
        _core.mask_invalid_and_grazing(args["depth"], args["invalid"], args["x"], args["y"],
                                       args["ray_norm2"], 100.0, 100.0, 0.03)


def test_a_read_only_depth_is_refused():
    z, invalid, x, y, _ = _args()
    z.setflags(write=False)
    with pytest.raises(ValueError, match="read-only"):
        _core.depth_to_world_points(z, invalid, x, y, np.eye(3, dtype=np.float32),
                                    np.zeros(3, dtype=np.float32))
