"""The C++ per-pixel passes of the simulated camera (``_core.mask_invalid_and_grazing``,
``_core.depth_to_world_points``, ``_core.metric_depth``, ``_core.add_quadratic_depth_noise``)
refuse bad arrays with a clear error instead of reading out of bounds; the last two equal
their numpy formulations bit for bit here, the first two on whole frames in
test_sim_camera.py."""

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


def _numpy_noise(z, draws, ref, sigma):
    """The camera's numpy formulation of the quadratic depth noise."""
    s = z / np.float32(ref)
    s **= np.float32(2.0)
    s *= np.float32(sigma)
    out = draws.copy()
    out *= s
    out += z
    return out


def test_noise_pass_equals_the_numpy_formulation_bit_for_bit():
    rng = np.random.default_rng(3)
    z = rng.uniform(0.05, 3.0, (48, 64)).astype(np.float32)
    z[0, :5] = [np.nan, 0.12, 3.0, 1e-3, np.float32(0.4)]
    draws = rng.standard_normal(z.shape, dtype=np.float32)
    out = draws.copy()
    _core.add_quadratic_depth_noise(z, out, float(np.float32(0.4)), float(np.float32(0.002)))
    assert np.array_equal(out, _numpy_noise(z, draws, 0.4, 0.002), equal_nan=True)
    assert not np.array_equal(out, z + draws * 0.002)  # the law is not a constant sigma


def test_metric_depth_pass_equals_the_numpy_linearisation_bit_for_bit():
    rng = np.random.default_rng(4)
    raw = rng.uniform(0.0, 1.0, (48, 64)).astype(np.float32)
    raw[0, :3] = [0.0, 1.0, 0.5]
    c, d = np.float32(-0.5037), np.float32(0.0151)
    z64 = raw[::-1].astype(np.float64)
    z64 += c
    np.divide(d, z64, out=z64)
    assert np.array_equal(_core.metric_depth(raw, float(c), float(d)), z64.astype(np.float32))


def test_noise_and_depth_passes_refuse_bad_arrays():
    z = np.ones((H, W), dtype=np.float32)
    with pytest.raises(ValueError, match="noise: expected shape"):
        _core.add_quadratic_depth_noise(z, np.ones((H, W + 1), dtype=np.float32), 0.4, 0.002)
    with pytest.raises(TypeError, match="noise: expected dtype float32"):
        _core.add_quadratic_depth_noise(z, np.ones((H, W)), 0.4, 0.002)
    with pytest.raises(TypeError, match="raw: expected dtype float32"):
        _core.metric_depth(np.ones((H, W)), -0.5, 0.01)


def test_normal_draws_are_a_seeded_standard_normal_stream():
    a = np.empty((480, 640), dtype=np.float32)
    b = np.empty_like(a)
    _core.fill_standard_normal(a, 17)
    _core.fill_standard_normal(b, 17)
    assert np.array_equal(a, b)  # the same seed, the same draws
    _core.fill_standard_normal(b, 18)
    assert np.mean(a == b) < 1e-3
    x = np.concatenate([a.ravel(), b.ravel()]).astype(np.float64)
    n = len(x)
    assert abs(x.mean()) < 5 / np.sqrt(n) and abs(x.std() - 1.0) < 5 * np.sqrt(0.5 / n)
    # tail shares (the ziggurat's tail beyond 3.44 and its wedges included), within 5 sigma
    for t, p in ((1.0, 0.3173105), (2.0, 0.0455003), (3.0, 0.0026998), (3.5, 0.000465)):
        share = np.mean(np.abs(x) > t)
        assert abs(share - p) < 5 * np.sqrt(p * (1 - p) / n), (t, share, p)
    assert np.all(np.isfinite(x)) and abs(np.mean(x > 0) - 0.5) < 5 * 0.5 / np.sqrt(n)


def test_normal_draws_refuse_bad_arrays_and_seeds():
    with pytest.raises(TypeError, match="out: expected dtype float32"):
        _core.fill_standard_normal(np.empty((H, W)), 1)
    with pytest.raises(ValueError, match="read-only"):
        frozen = np.empty((H, W), dtype=np.float32)
        frozen.flags.writeable = False
        _core.fill_standard_normal(frozen, 1)
    with pytest.raises(TypeError):
        _core.fill_standard_normal(np.empty((H, W), dtype=np.float32), -1)


def test_world_points_equal_the_float32_formulation_bit_for_bit():
    # a width that is no multiple of a vector's lanes; invalid pixels and NaN depths
    rng = np.random.default_rng(7)
    h, w = 7, 37
    z = rng.uniform(0.2, 1.5, (h, w)).astype(np.float32)
    z[rng.random((h, w)) < 0.1] = np.nan
    invalid = rng.random((h, w)) < 0.1
    x = rng.uniform(-0.6, 0.6, w).astype(np.float32)
    y = rng.uniform(-0.5, 0.5, h).astype(np.float32)
    R = np.linalg.qr(rng.normal(size=(3, 3)))[0].astype(np.float32)
    t = rng.normal(size=3).astype(np.float32)
    zp = np.where(invalid, np.float32(np.nan), z)
    X, Y = np.broadcast_to(x, (h, w)), np.broadcast_to(y[:, None], (h, w))
    want = np.stack([((R[i, 0] * X + R[i, 1] * Y) + R[i, 2]) * zp + t[i] for i in range(3)], axis=-1)
    got = _core.depth_to_world_points(z, invalid, x, y, R, t)
    assert np.array_equal(got.reshape(h, w, 3), want.astype(np.float32), equal_nan=True)
    assert np.array_equal(z, zp, equal_nan=True)  # the invalid pixels' depth became NaN
