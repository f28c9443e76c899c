"""Finite but absurd coordinates, huge counts of identical rows, and clusters below the plane.

Regressions:
- >= 16 identical rows at ~3.4e38 (float32 max) aborted the interpreter inside FLANN
  (``kdtree_single_index.h: Assertion 'index > 0 && index < count'``). Points with any
  |coordinate| > ``max_abs_coordinate_m`` (scene filter parameter, default 1000 m) are now
  dropped and counted like NaN rows, at every entry that takes points.
- 100k identical rows took ~6 minutes in the per-point (voxel 0) clustering.
- ``estimate_object`` on points below the plane returned a negative height.
Crash-prone cases run in a child interpreter (``isolated.run_isolated``).
"""

import time

import numpy as np
import pytest

from grasp_pipeline import _core
from grasp_pipeline.assets import default_config_dir
from grasp_pipeline.config import read_yaml
from grasp_pipeline.perception import SceneFilterConfig
from grasp_pipeline.robot.depth_noise import DepthNoiseConfig
from isolated import describe, run_isolated
from test_core_bindings import cube_cloud, table_cloud

F32_MAX = float(np.finfo(np.float32).max)
PLANE = _core.Plane([0, 0, 1], -0.2)


def absurd_rows(n=16, value=F32_MAX):
    return np.full((n, 3), value, np.float32)


def scene_with(extra):
    return np.vstack([table_cloud(5000), cube_cloud((0.5, 0.0)), extra]).astype(np.float32)


def test_coordinate_bound_defaults_agree_in_cpp_python_and_yaml():
    yaml_value = read_yaml(default_config_dir() / "scene_filter.yaml")["max_abs_coordinate_m"]
    assert _core.SceneFilterParams().max_abs_coordinate_m == 1000.0
    assert SceneFilterConfig().max_abs_coordinate_m == 1000.0
    assert yaml_value == 1000.0
    assert SceneFilterConfig().to_core(DepthNoiseConfig()).max_abs_coordinate_m == 1000.0


@pytest.mark.parametrize("voxel", [0.003, 0.0])
def test_sixteen_rows_at_float_max_do_not_abort_the_scene_filter(voxel):
    code = f"""
import numpy as np
from grasp_pipeline import _core
from test_core_bindings import table_cloud, cube_cloud
big = np.full((16, 3), np.finfo(np.float32).max, np.float32)
pts = np.vstack([table_cloud(5000), cube_cloud((0.5, 0.0)), big]).astype(np.float32)
p = _core.SceneFilterParams(); p.cluster_voxel_m = {voxel}
r = _core.SceneFilter(p).process(pts)
print(r.num_out_of_range, len(r.cluster_ids))
r = _core.euclidean_clusters(big, 0.015, 2, 0.0, 0.3, {voxel})
print(r.num_out_of_range)
"""
    res = run_isolated(code)
    assert res.returncode == 0, describe(res)
    assert res.stdout.split() == ["16", "1", "16"]


def test_out_of_range_rows_are_labelled_invalid_counted_and_reported_once(caplog):
    from grasp_pipeline.perception import PerceptionSession

    extra = np.vstack([absurd_rows(16), [[0.5, 0.0, 1000.5]], [[0.5, 0.0, 999.5]],
                       [[np.nan, 0, 0]]]).astype(np.float32)
    pts = scene_with(extra)
    ref = _core.SceneFilter(_core.SceneFilterParams()).process(scene_with(np.zeros((0, 3))))
    res = _core.SceneFilter(_core.SceneFilterParams()).process(pts)
    assert res.num_out_of_range == 17 and res.num_invalid == 18
    assert res.num_valid + res.num_invalid == len(pts) and res.max_abs_coordinate_m == 1000.0
    tail = res.labels[-len(extra):]
    assert np.all(tail[:17] == _core.LABEL_INVALID) and tail[17] != _core.LABEL_INVALID
    assert np.array_equal(res.labels[:len(ref.labels)], ref.labels)
    session = PerceptionSession()
    with caplog.at_level("DEBUG", logger="grasp_pipeline.perception"):
        session.process(pts, [0.5, 0, 0.6], 0.0)
        session.process(pts, [0.5, 0, 0.6], 0.1)
    warned = [r for r in caplog.records if "max_abs_coordinate_m" in r.getMessage()]
    assert [r.levelname for r in warned] == ["WARNING", "DEBUG"]
    assert "+-1000 m" in warned[0].getMessage()


def test_the_bound_is_a_parameter_and_float64_beyond_float_range_is_out_of_range():
    pts = np.vstack([table_cloud(3000), [[0.5, 0.0, 1500.0]], [[1e300, 0, 0]]])
    p = _core.SceneFilterParams()
    assert _core.SceneFilter(p).process(pts).num_out_of_range == 2
    p.max_abs_coordinate_m = 2000.0
    assert _core.SceneFilter(p).process(pts).num_out_of_range == 1
    p.max_abs_coordinate_m = 0.0
    with pytest.raises(ValueError, match="max_abs_coordinate_m"):
        _core.SceneFilter(p)


def test_absurd_clouds_cost_no_more_than_normal_ones():
    normal = table_cloud(200_000).astype(np.float32)
    absurd = normal.copy()
    absurd[::2] = F32_MAX  # half the rows garbage
    absurd[1::4] = -F32_MAX
    f = _core.SceneFilterParams()

    def best_ms(pts):
        return min(_core.SceneFilter(f).process(pts).ms_total for _ in range(3))

    assert best_ms(absurd) <= 1.5 * best_ms(normal) + 5.0


@pytest.mark.parametrize("voxel", [0.003, 0.0])
def test_100k_identical_rows_are_fast(voxel):
    dup = np.tile(np.float32([[0.5, 0.0, 0.3]]), (100_000, 1))
    pts = np.vstack([table_cloud(300_000).astype(np.float32), dup])
    p = _core.SceneFilterParams()
    p.cluster_voxel_m = voxel
    t0 = time.perf_counter()
    res = _core.SceneFilter(p).process(pts)
    assert time.perf_counter() - t0 < 3.0  # was ~6 minutes with voxel 0
    assert res.num_candidates == 100_000 and res.clusters[0].num_points == 100_000
    t0 = time.perf_counter()
    est = _core.estimate_object(dup, PLANE, _core.ObbParams(), band=0.01)
    assert est.estimate is None and "coincide" in est.failure
    assert _core.pca_box(dup) is None
    assert time.perf_counter() - t0 < 1.0


def test_fine_grained_functions_drop_out_of_range_rows():
    table = table_cloud(3000)
    bad = np.vstack([table, absurd_rows(20).astype(np.float64), [[0.4, 0.0, -2000.0]]])
    params = _core.SceneFilterParams()
    fit_ref = _core.fit_plane_ransac(table, params, seed=3)
    fit = _core.fit_plane_ransac(bad, params, seed=3)
    assert fit is not None and fit.plane.height_m == pytest.approx(fit_ref.plane.height_m, abs=1e-6)
    planes = _core.extract_planes(bad.astype(np.float32), params)
    assert planes and planes[0].count_whole == _core.extract_planes(table.astype(np.float32), params)[0].count_whole
    cube = cube_cloud((0.5, 0.0))
    cl = _core.euclidean_clusters(np.vstack([cube, absurd_rows(20)]), 0.015, 20, 0.0, 0.3, 0.0)
    assert cl.num_accepted == 1 and cl.num_out_of_range == 20 and cl.num_invalid == 20
    assert np.all(cl.labels[-20:] == _core.LABEL_INVALID)
    with pytest.raises(ValueError, match="max_abs_coordinate_m"):
        _core.euclidean_clusters(cube, 0.015, 20, 0.0, 0.3, 0.0, max_abs_coordinate_m=0.0)
    mixed = np.vstack([cube, np.full((20, 3), 1e30)])
    est = _core.estimate_object(mixed, PLANE, _core.ObbParams(), band=0.01)
    ref = _core.estimate_object(cube, PLANE, _core.ObbParams(), band=0.01)
    assert est.estimate.num_points == len(cube)
    assert np.allclose(est.estimate.center, ref.estimate.center)
    assert np.allclose(_core.pca_box(mixed).center, _core.pca_box(cube).center)
    (pr,) = _core.estimate_with_priors([mixed], PLANE, _core.ObbParams(), _core.Tracker(_core.ObbParams()))
    assert pr.estimate.num_points == len(cube)
    # a larger bound lets them in (and the box then fails: garbage in, no estimate out)
    wide = _core.estimate_object(mixed, PLANE, _core.ObbParams(), max_abs_coordinate_m=1e9)
    assert wide.estimate.num_points == len(cube)


def box_points(z_lo, z_hi, n=3000, seed=0):
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.uniform(0.45, 0.5, n), rng.uniform(-0.025, 0.025, n),
                            rng.uniform(z_lo, z_hi, n)])


def test_a_cluster_below_the_plane_has_no_estimate():
    below = box_points(0.12, 0.17)  # top 30 mm below the table at z = 0.2
    res = _core.estimate_object(below, PLANE, _core.ObbParams(), band=0.01)
    assert res.estimate is None
    assert "not above the plane" in res.failure and "below the plane" in res.failure
    tr = _core.Tracker(_core.ObbParams())
    (r,) = _core.estimate_with_priors([below], PLANE, _core.ObbParams(), tr, band=0.01)
    assert r.estimate is None and "not above the plane" in r.failure
    # straddling the plane: an estimate, height >= 0, judged by the guards
    straddle = box_points(0.17, 0.22)
    est = _core.estimate_object(straddle, PLANE, _core.ObbParams(), band=0.01).estimate
    assert est is not None and est.height_m > 0 and est.extents[2] >= 0
    # just above the plane but lower than min_height: the "too low" guard refuses it
    flat = box_points(0.2005, 0.2015)
    low = _core.estimate_object(flat, PLANE, _core.ObbParams(), band=0.01).estimate
    assert low is not None and not low.grasp_ok and any("too low" in n for n in low.notes)
