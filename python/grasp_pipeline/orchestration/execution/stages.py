"""The stages of one pick, as results and reports name them (``failed_stage``, ``stages``).

:class:`Stage` is a ``str``: a member equals, hashes, formats and serializes as its name
(``Stage.LIFT == "LIFT"``, ``f"{Stage.LIFT}" == "LIFT"``, JSON ``"LIFT"``), so reports and the
code that reads them by name see plain strings.
"""

from __future__ import annotations

from enum import Enum


class Stage(str, Enum):
    """A stage of one pick: the selection, the grasp source, the grasp action's stages (method.md §7
    and PLACE), and the check that a picked object arrived (``VERIFY``)."""

    SELECT = "SELECT"        # select the target and wait for its published grasps
    GRASP = "GRASP"          # ask the grasp source; start the grasp action
    PRE_GRASP = "PRE_GRASP"  # plan, open, move to the pre-grasp
    APPROACH = "APPROACH"    # straight line to the contact point
    CLOSE = "CLOSE"          # close until the fingers stall
    LIFT = "LIFT"            # lift and check the hold
    DONE = "DONE"            # grasped
    PLACE = "PLACE"          # carry to the tray, lower, release, look
    VERIFY = "VERIFY"        # picked, but not placed in the tray

    def __str__(self) -> str:
        return self.value

    def __format__(self, spec: str) -> str:
        return format(self.value, spec)
