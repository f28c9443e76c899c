"""The perceived scene: frames → perception → tracks (:mod:`.perception_loop`), the scene's
labelled points (:mod:`.scene_cloud`) and boxes (:mod:`.scene_model`), track look-ups
(:mod:`.tracks`), the selection of a target by position (:mod:`.selection`) and the targets
picked when the user names none (:mod:`.targets`)."""
