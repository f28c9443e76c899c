"""The simulated world: a Franka Panda with an eye-in-hand depth camera in MuJoCo.

Modules (one concept each):

* :mod:`.gl_backend` — choose the headless GL backend before MuJoCo is imported
  (:func:`~.gl_backend.configure_gl`) and make renderers only where a context can exist.
* :mod:`.scene_spec` — dataclasses describing a scene (objects: kind, size, pose).
* :mod:`.scenes` — the reference scene (method.md §8) and a seeded random scene generator.
* :mod:`.world` — :class:`~.world.SimWorld`: builds and steps the world and implements the
  robot protocols of :mod:`grasp_pipeline.robot.protocols` (arm, gripper, camera, contacts).
* :mod:`.camera` — :class:`~.camera.DepthCamera`: GL rendering or a ray-cast fallback,
  depth noise, organized world point clouds.
* :mod:`.work_cell` — the table top and the tray as boxes, read from the model.
* :mod:`.scene_view` — renders the fixed third-person view the run's video shows.
* :mod:`.ground_truth` — object poses and sizes **for evaluation code only**.

The robot's description (names, limits, frames) is :mod:`grasp_pipeline.robot.description`.
Importing this package does nothing: no MuJoCo, no GL context, no environment changes.
"""
