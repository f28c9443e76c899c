"""The robot as the pipeline knows it, independent of any simulator.

* :mod:`.description` — the Franka Panda's names, published limits, gripper and camera mount,
  read from our MJCF (MuJoCo's *model* used as a kinematics library; no world, no GL).
* :mod:`.protocols` — what the pipeline needs from a robot: :class:`~.protocols.Arm`,
  :class:`~.protocols.Gripper`, :class:`~.protocols.Camera`,
  :class:`~.protocols.ContactMonitor` and the :class:`~.protocols.Clock` that paces them.
  ``grasp_pipeline.sim.world.SimWorld`` implements them; a real robot would too.
* :mod:`.frame` — :class:`~.frame.Frame`, what one camera capture delivers
  (:meth:`~.frame.Frame.from_depth` builds one from a depth image in metres).
* :mod:`.frame_contract` — :func:`~.frame_contract.check_frame`: the camera contract (depth in
  metres, sane intrinsics, a rigid pose at capture, matching shapes), checked on every frame
  that enters the pipeline (docs/real_robot.md).

``motion``, ``perception`` and ``orchestration`` import this package, never
``grasp_pipeline.sim``.
"""
