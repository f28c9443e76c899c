"""Motion layer: target pose or joint goal → timed, collision-free joint trajectory.

Pieces, as OMPL separates them (one concept per module):

* :mod:`.config` — :class:`MotionConfig` from ``config/motion.yaml``;
* :mod:`.ik` — :class:`PandaIK` (frankik candidates refined/verified on our MuJoCo model);
* :mod:`.robot_spheres` — the robot as spheres; :mod:`.kinematics` — batch FK;
* :mod:`.occupancy` — :class:`OccupancyMap` (voxels + distance field) and :class:`OrientedBox`;
* :mod:`.validity` — :class:`StateValidator` (limits + self + environment + boxes + floor);
* :mod:`.core_checker` — export of the robot and the scene to the C++ ``_core.StateChecker``
  that :class:`StateValidator` and OMPL call (the numpy code stays as the reference);
* :mod:`.state_space` / :mod:`.planner` — OMPL wiring and :class:`JointPlanner`;
* :mod:`.cartesian` — :class:`CartesianPlanner` (straight approach / lift lines);
* :mod:`.timing` — :class:`TrajectoryTimer` (TOPP-RA); :mod:`.trajectory` — result types;
* :mod:`.executor` — :class:`TrajectoryExecutor` (runs in ``SimWorld``, monitors, stops safely);
* :mod:`.perceived_scene` — :class:`PerceivedScene` (what perception hands to planning);
* :mod:`.grasp_poses` — top-down grasp / pre-grasp / lift TCP poses;
* :mod:`.motion_planner` — :class:`MotionPlanner`, the facade the orchestrator uses.

Import the submodules directly (``from grasp_pipeline.motion.motion_planner import
MotionPlanner``); this package file imports nothing heavy.
"""
