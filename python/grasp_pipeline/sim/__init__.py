"""The simulated world: a Franka Panda with an eye-in-hand depth camera in MuJoCo.

Modules (one concept each):

* :mod:`.robot_model` — robot names, Franka limits, flange/TCP/camera frames read from the MJCF.
* :mod:`.scene_spec` — dataclasses describing a scene (objects: kind, size, pose).
* :mod:`.scenes` — the reference scene (SPEC section 8) and a seeded random scene generator.
* :mod:`.world` — :class:`~.world.SimWorld`: build, step, follow joint trajectories, gripper,
  readouts, contacts, depth frames.
* :mod:`.camera` — :class:`~.camera.DepthCamera`: EGL/OSMesa rendering or a ray-cast fallback,
  depth noise, organized world point clouds.
* :mod:`.frame` — :class:`~.frame.Frame`, what one capture delivers.
* :mod:`.ground_truth` — object poses and sizes **for evaluation code only**; perception,
  planning and execution must never import it.

Submodules are imported on demand (``from grasp_pipeline.sim.world import SimWorld``) so that
importing this package does not start MuJoCo or a GL context.
"""

from .gl_backend import select_gl_backend as _select_gl_backend

#: The ``MUJOCO_GL`` value in effect for this process (see :mod:`.gl_backend`).
GL_BACKEND = _select_gl_backend()
