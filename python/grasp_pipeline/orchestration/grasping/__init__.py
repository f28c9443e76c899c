"""Where grasps come from: the :class:`~.source.GraspSource` protocol and its request
(:mod:`.source`), the sources — any side (:mod:`.any_side` with its sampler's modules),
top-down (:mod:`.top_down`, fitted to the points by :mod:`.fit`), fixed poses
(:mod:`.fixed`) — and the names ``grasp.grasp_source`` selects them by (:mod:`.registry`);
what makes an object graspable: what carries it (:mod:`.support`) and the free space for the
fingers (:mod:`.accessibility`)."""
