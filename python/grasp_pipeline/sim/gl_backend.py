"""Headless OpenGL for MuJoCo: choose the backend before MuJoCo is imported, and create
renderers only where a context can really be made.

MuJoCo's Python bindings read ``MUJOCO_GL`` once, when ``mujoco`` is first imported, and
fix their GL platform then; a process cannot switch later. So:

* :func:`configure_gl` — call it before anything imports ``mujoco`` (every console command
  does, first thing). ``MUJOCO_GL`` set by the user is respected; otherwise ``egl`` then
  ``osmesa`` are tried, each in a short child process that makes a tiny renderer (about 1 s,
  once; the choice is written to ``MUJOCO_GL`` so worker processes inherit it); when none
  works, ``MUJOCO_GL=disable`` and the depth camera ray-casts. Importing this module does
  nothing.
* :func:`new_renderer` — the only place a renderer (``mujoco.Renderer`` or the depth
  camera's :class:`~.rgbd_renderer.RgbdRenderer`) is made. It refuses with
  :class:`~.exceptions.RenderUnavailable` (a clean Python error) when no context can exist:
  GL disabled, or MuJoCo's default GLFW platform without a display (trying that aborts the
  process), or an earlier attempt in this process failed (a second attempt can abort too).
"""

from __future__ import annotations

import logging
import os
import subprocess
import sys
from typing import Any, Callable, Optional

from .exceptions import RenderUnavailable

log = logging.getLogger(__name__)

#: Backends tried in order when ``MUJOCO_GL`` is not set.
GL_CANDIDATES: tuple[str, ...] = ("egl", "osmesa")
#: Value of ``MUJOCO_GL`` that disables GL in MuJoCo's bindings.
GL_DISABLED = "disable"
#: Values MuJoCo reads as "no GL at all".
GL_OFF_VALUES: tuple[str, ...] = ("disable", "disabled", "off", "false", "0")
#: Values under which MuJoCo uses GLFW, which needs a display on Linux.
GLFW_VALUES: tuple[str, ...] = ("", "glfw", "glx", "enable", "enabled", "on", "true", "1")
_PROBE_TIMEOUT_S = 30.0
_PROBE_CODE = (
    "import mujoco\n"
    "r = mujoco.Renderer(mujoco.MjModel.from_xml_string('<mujoco/>'), 8, 8)\n"
    "r.enable_depth_rendering()\n"
    "r.render()\n"
    "r.close()\n"
)
_failure: Optional[str] = None  # why GL failed in this process (never try twice)


def _probe(backend: str) -> bool:
    env = dict(os.environ, MUJOCO_GL=backend)
    env.pop("PYOPENGL_PLATFORM", None)
    try:
        res = subprocess.run([sys.executable, "-c", _PROBE_CODE], env=env, capture_output=True,
                             timeout=_PROBE_TIMEOUT_S, check=False)
    except (OSError, subprocess.TimeoutExpired) as exc:
        log.debug("GL probe %s failed: %s", backend, exc)
        return False
    if res.returncode != 0:
        log.debug("GL probe %s failed: %s", backend, res.stderr.decode(errors="replace")[-400:])
    return res.returncode == 0


def configure_gl() -> str:
    """Make ``MUJOCO_GL`` name a working headless backend; return the value in effect.

    Returns ``"egl"``, ``"osmesa"``, a user's own choice, ``"disable"`` (ray-cast only), or
    the value MuJoCo already read when it was imported before this call (then nothing can
    change; :func:`new_renderer` still refuses what cannot work).

    Software GL (Mesa's llvmpipe) rasterizes on the calling thread unless ``LP_NUM_THREADS``
    is set: its render threads cost more CPU in hand-offs than they save on a 640x480 depth
    frame (about 10 % of a frame's render CPU), and benchmark workers run one per core. The
    images are the same bit for bit."""
    os.environ.setdefault("LP_NUM_THREADS", "0")
    current = os.environ.get("MUJOCO_GL")
    if current is not None:
        return current.strip().lower()
    if "mujoco" in sys.modules:
        return gl_in_effect()
    for backend in GL_CANDIDATES:
        if _probe(backend):
            os.environ["MUJOCO_GL"] = backend
            log.info("headless GL backend: %s (MUJOCO_GL was not set)", backend)
            return backend
    os.environ["MUJOCO_GL"] = GL_DISABLED
    log.warning("no headless GL backend works (tried %s); depth frames will be ray-cast and "
                "no video is rendered", ", ".join(GL_CANDIDATES))
    return GL_DISABLED


def gl_in_effect() -> str:
    """The ``MUJOCO_GL`` value the imported MuJoCo uses (the environment's if not imported)."""
    mod = sys.modules.get("mujoco.rendering.classic.gl_context")
    value = getattr(mod, "_MUJOCO_GL", None) if mod is not None else None
    if value is None:
        value = os.environ.get("MUJOCO_GL", "")
    return str(value).strip().lower()


def gl_unavailable_reason() -> Optional[str]:
    """Why no GL context can be made in this process, or None when one may be tried."""
    if _failure is not None:
        return _failure
    gl = gl_in_effect()
    if gl in GL_OFF_VALUES:
        return f"MUJOCO_GL={gl}"
    if gl in GLFW_VALUES and sys.platform.startswith("linux") and not os.environ.get("DISPLAY"):
        return (f"MuJoCo was imported with MUJOCO_GL={gl or '(unset)'} (GLFW) and there is no "
                "display; call grasp_pipeline.sim.gl_backend.configure_gl() before importing "
                "mujoco, or set MUJOCO_GL=egl or osmesa")
    return None


def new_renderer(model, height_px: int, width_px: int,
                 renderer_class: Optional[Callable[..., Any]] = None):
    """A ``renderer_class(model, height_px, width_px)`` (default ``mujoco.Renderer``), or
    :class:`RenderUnavailable` when none can be made here."""
    global _failure
    reason = gl_unavailable_reason()
    if reason is not None:
        raise RenderUnavailable(f"no GL rendering: {reason}")
    import mujoco

    vis = model.vis.global_
    vis.offwidth = max(int(vis.offwidth), int(width_px))
    vis.offheight = max(int(vis.offheight), int(height_px))
    try:
        make = mujoco.Renderer if renderer_class is None else renderer_class
        return make(model, int(height_px), int(width_px))
    except RenderUnavailable:
        raise
    except Exception as exc:  # any GL failure: missing library, no device, ...
        _failure = f"GL context creation failed with MUJOCO_GL={gl_in_effect() or '(unset)'}: {exc}"
        raise RenderUnavailable(_failure) from exc
