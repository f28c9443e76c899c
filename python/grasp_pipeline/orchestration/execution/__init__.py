"""Acting on a chosen grasp: the grasp action (:mod:`.grasp_action`) and its stages
(:mod:`.stages`), planning it (:mod:`.grasp_planning`), the gripper's moves
(:mod:`.gripper_moves`), placing into the tray (:mod:`.place`, :mod:`.place_config`,
:mod:`.tray`, :mod:`.tray_spots`, :mod:`.tray_check`) and the client of the motion planner
(:mod:`.motion_client`)."""
