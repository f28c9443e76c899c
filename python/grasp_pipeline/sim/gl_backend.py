"""Choosing the headless OpenGL backend for MuJoCo *before* MuJoCo is imported.

MuJoCo's Python bindings read ``MUJOCO_GL`` once, when ``mujoco`` is first imported, and
PyOpenGL fixes its platform at the same moment; a process cannot switch later. So the choice
happens when :mod:`grasp_pipeline.sim` is imported:

1. ``MUJOCO_GL`` set by the user → respected as is.
2. otherwise, if ``mujoco`` is not imported yet: try ``egl``, then ``osmesa``, each in a short
   child process that creates a tiny renderer (about 1 s, once; the result is written to
   ``MUJOCO_GL`` so child processes inherit it).
3. no GL works → ``MUJOCO_GL=disable``; the depth camera then uses the ray-cast fallback
   (:mod:`grasp_pipeline.sim.camera`), which produces the same frames.

If ``mujoco`` was imported before this package without ``MUJOCO_GL``, nothing can be changed;
the camera will try to render and fall back to ray casting if that fails.
"""

from __future__ import annotations

import logging
import os
import subprocess
import sys

log = logging.getLogger(__name__)

#: Backends tried in order when ``MUJOCO_GL`` is not set.
GL_CANDIDATES: tuple[str, ...] = ("egl", "osmesa")
#: Value of ``MUJOCO_GL`` that disables GL in MuJoCo's bindings.
GL_DISABLED = "disable"
_PROBE_TIMEOUT_S = 30.0
_PROBE_CODE = (
    "import mujoco\n"
    "r = mujoco.Renderer(mujoco.MjModel.from_xml_string('<mujoco/>'), 8, 8)\n"
    "r.enable_depth_rendering()\n"
    "r.render()\n"
    "r.close()\n"
)


def _probe(backend: str) -> bool:
    env = dict(os.environ, MUJOCO_GL=backend)
    env.pop("PYOPENGL_PLATFORM", None)
    try:
        res = subprocess.run(
            [sys.executable, "-c", _PROBE_CODE],
            env=env,
            capture_output=True,
            timeout=_PROBE_TIMEOUT_S,
            check=False,
        )
    except (OSError, subprocess.TimeoutExpired) as exc:
        log.debug("GL probe %s failed: %s", backend, exc)
        return False
    if res.returncode != 0:
        log.debug("GL probe %s failed: %s", backend, res.stderr.decode(errors="replace")[-400:])
    return res.returncode == 0


def select_gl_backend() -> str:
    """Make sure ``MUJOCO_GL`` names a working headless backend; return the chosen name.

    Returns the value in effect: ``"egl"``, ``"osmesa"``, a user's own choice, ``"disable"``
    (ray-cast only), or ``""`` when ``mujoco`` was already imported without ``MUJOCO_GL``.
    """
    current = os.environ.get("MUJOCO_GL")
    if current is not None:
        return current.strip().lower()
    if "mujoco" in sys.modules:
        log.warning(
            "mujoco was imported before grasp_pipeline.sim without MUJOCO_GL; the GL backend "
            "cannot be chosen any more (set MUJOCO_GL=egl or osmesa to render)"
        )
        return ""
    for backend in GL_CANDIDATES:
        if _probe(backend):
            os.environ["MUJOCO_GL"] = backend
            log.info("headless GL backend: %s (MUJOCO_GL was not set)", backend)
            return backend
    os.environ["MUJOCO_GL"] = GL_DISABLED
    log.warning("no headless GL backend works (tried %s); depth frames will be ray-cast",
                ", ".join(GL_CANDIDATES))
    return GL_DISABLED
