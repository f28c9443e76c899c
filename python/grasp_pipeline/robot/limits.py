"""The Franka Panda's and the Franka Hand's published limits: the one definition of each.

Franka's published figures (the robot's datasheet; see third_party_notes.md). This module
imports only numpy, so that the parameter checks (:mod:`grasp_pipeline.config_ranges`) and the
perception and grasp settings can bound their values by the robot's own figures without loading
MuJoCo; :mod:`.description` re-exports them with the robot's names and frames, and our MJCF
(``sim/panda.xml``) is checked against them by the tests.
"""

from __future__ import annotations

import numpy as np

# Franka Panda joint limits [rad, rad/s, rad/s^2, N m].
PANDA_Q_MIN = np.array([-2.8973, -1.7628, -2.8973, -3.0718, -2.8973, -0.0175, -2.8973])
PANDA_Q_MAX = np.array([2.8973, 1.7628, 2.8973, -0.0698, 2.8973, 3.7525, 2.8973])
PANDA_QD_MAX = np.array([2.1750, 2.1750, 2.1750, 2.1750, 2.6100, 2.6100, 2.6100])
PANDA_QDD_MAX = np.array([15.0, 7.5, 10.0, 12.5, 15.0, 20.0, 20.0])
PANDA_TAU_MAX = np.array([87.0, 87.0, 87.0, 87.0, 12.0, 12.0, 12.0])
for _a in (PANDA_Q_MIN, PANDA_Q_MAX, PANDA_QD_MAX, PANDA_QDD_MAX, PANDA_TAU_MAX):
    _a.setflags(write=False)

#: Maximum finger gap of the Franka Hand [m] (its largest opening).
GRIPPER_MAX_WIDTH_M = 0.08
#: Largest grasping force of the Franka Hand [N] (70 N continuous).
GRIPPER_MAX_FORCE_N = 140.0
