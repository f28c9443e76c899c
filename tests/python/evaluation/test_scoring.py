"""Ground-truth scoring: yaw symmetry and the side a width is compared with."""

import math

import numpy as np
import pytest

from grasp_pipeline.evaluation.scoring import _closing_axis, _yaw_error_deg
from grasp_pipeline.sim.ground_truth import ObjectTruth

TOL_M = 0.002  # obb.width_tol_m


def _truth(kind: str, size, yaw_deg: float) -> ObjectTruth:
    a = math.radians(yaw_deg)
    T = np.eye(4)
    T[:2, :2] = [[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]]
    return ObjectTruth("o", kind, tuple(size), T, T.copy())


def _dir(deg: float) -> np.ndarray:
    return np.array([math.cos(math.radians(deg)), math.sin(math.radians(deg))])


def test_clear_cuboid_closing_on_the_long_side_is_a_90_deg_error():
    t = _truth("cuboid", (0.03, 0.06, 0.05), 10.0)
    assert _yaw_error_deg(_dir(10.3), t, TOL_M) == pytest.approx(0.3, abs=1e-9)
    assert _yaw_error_deg(_dir(100.0), t, TOL_M) == pytest.approx(90.0, abs=1e-9)
    assert _closing_axis(t, _dir(100.0), TOL_M)[0] == 0  # still compared with the narrow side


def test_near_square_cuboid_has_two_equivalent_closing_directions():
    t = _truth("cuboid", (0.050, 0.0515, 0.05), 10.0)  # sides 1.5 mm apart < width_tol_m
    assert _yaw_error_deg(_dir(100.4), t, TOL_M) == pytest.approx(0.4, abs=1e-9)
    k, sym = _closing_axis(t, _dir(100.4), TOL_M)
    assert (k, sym) == (1, 90.0)  # width compared with the side it closes on


def test_cube_mod_90_and_cylinder_undefined():
    assert _yaw_error_deg(_dir(-44.0), _truth("cube", (0.05,) * 3, 46.0), TOL_M) == pytest.approx(0.0, abs=1e-9)
    assert _yaw_error_deg(_dir(30.0), _truth("cylinder", (0.05, 0.05, 0.08), 0.0), TOL_M) is None
