"""The GL backend is chosen before MuJoCo is imported; where no context can exist, renderers
are refused cleanly (ray-cast camera, no video) instead of aborting the process."""

import os
import subprocess
import sys

import pytest

LIBRARY_USER = """
import mujoco                      # imported first, MUJOCO_GL unset: MuJoCo binds GLFW
from grasp_pipeline.sim.world import SimWorld
from grasp_pipeline.sim.scene_view import SceneView
from grasp_pipeline.sim.exceptions import RenderUnavailable
w = SimWorld()
print("camera", w.camera.backend)
try:
    SceneView(w)
except RenderUnavailable as exc:
    print("refused", "configure_gl" in str(exc))
w.capture()
w.close()
"""


def _env(**extra):
    env = {k: v for k, v in os.environ.items() if k not in ("MUJOCO_GL", "DISPLAY", "PYOPENGL_PLATFORM")}
    env.update(extra)
    return env


def test_mujoco_imported_first_without_gl_gives_a_raycast_camera_and_no_abort():
    res = subprocess.run([sys.executable, "-c", LIBRARY_USER], env=_env(), capture_output=True,
                         text=True, timeout=300)
    assert res.returncode == 0, res.stderr[-3000:]
    assert "camera raycast" in res.stdout and "refused True" in res.stdout


@pytest.mark.parametrize("value", ["egl", "osmesa", "disable"])
def test_a_user_choice_is_respected(value):
    code = "from grasp_pipeline.sim.gl_backend import configure_gl; print(configure_gl())"
    res = subprocess.run([sys.executable, "-c", code], env=_env(MUJOCO_GL=value), capture_output=True,
                         text=True, timeout=120)
    assert res.stdout.strip() == value


def test_without_a_choice_a_working_backend_is_found_and_inherited_by_children():
    code = CHILD_CHECK
    res = subprocess.run([sys.executable, "-c", code], env=_env(), capture_output=True, text=True, timeout=120)
    chosen, child = res.stdout.split()
    assert chosen in ("egl", "osmesa", "disable") and child == chosen


CHILD_CHECK = """
import os, subprocess, sys
from grasp_pipeline.sim.gl_backend import configure_gl
v = configure_gl()
c = subprocess.run([sys.executable, "-c", "import os; print(os.environ['MUJOCO_GL'])"],
                   capture_output=True, text=True).stdout.strip()
print(v, c)
"""


@pytest.mark.parametrize("user_value", [None, "3"])
def test_software_gl_rasterizes_on_the_calling_thread_unless_the_user_says_otherwise(user_value):
    code = ("import os; from grasp_pipeline.sim.gl_backend import configure_gl; configure_gl(); "
            "print(os.environ['LP_NUM_THREADS'])")
    env = {k: v for k, v in _env(MUJOCO_GL="egl").items() if k != "LP_NUM_THREADS"}
    if user_value is not None:
        env["LP_NUM_THREADS"] = user_value
    res = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    assert res.stdout.strip() == (user_value or "0"), res.stderr[-2000:]


def test_frames_are_the_same_whatever_the_software_rasterizer_threads():
    """llvmpipe's render threads change what a frame costs, not what it shows."""
    code = """
import hashlib
from grasp_pipeline.sim.gl_backend import configure_gl
configure_gl()
from grasp_pipeline.sim.scenes import random_scene
from grasp_pipeline.sim.world import SimWorld
w = SimWorld(random_scene(3))
f = w.camera.capture()
print(w.camera.backend, hashlib.sha1(f.depth.tobytes() + f.rgb.tobytes()).hexdigest())
w.close()
"""
    out = set()
    for threads in ("0", "2"):
        res = subprocess.run([sys.executable, "-c", code], env=_env(LP_NUM_THREADS=threads),
                             capture_output=True, text=True, timeout=300)
        assert res.returncode == 0, res.stderr[-3000:]
        out.add(res.stdout.split()[-1])
        backend = res.stdout.split()[0]
    assert len(out) == 1, f"{backend} frames differ with the rasterizer's threads"
