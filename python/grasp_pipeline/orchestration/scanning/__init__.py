"""Looking at the scene before a pick: the active scan (:mod:`.scan`), which segments it looks
at again from closer above (:mod:`.ambiguity`), and the look at a target's unseen sides
(:mod:`.side_view`)."""
