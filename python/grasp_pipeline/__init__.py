"""grasp_pipeline — classical robot grasping without ROS.

Perception core in C++ (``grasp_pipeline._core``: Eigen + PCL), a simulated Franka
Panda in MuJoCo (``grasp_pipeline.sim``), motion with OMPL and TOPP-RA
(``grasp_pipeline.motion``) and the orchestration that ties them together.

Sub-packages are imported lazily so that, e.g., the simulator can be used without
the compiled extension and vice versa.
"""

__version__ = "0.1.0"
