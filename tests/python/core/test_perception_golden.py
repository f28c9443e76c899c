"""Regression: the per-frame perception outputs equal those of the implementation before
the speed work, exactly (labels of every row, planes, estimates, views, tids, tracks), floats
to a few ulps (the last bit depends on the CPU: see perception_golden.FLOAT_REL_TOL).

See perception_golden.py for what is pinned and how the golden file was recorded.
"""

import json

from perception_golden import GOLDEN_PATH, describe_differences, matches, session_digest


def test_per_frame_outputs_equal_the_recorded_reference():
    golden = json.loads(GOLDEN_PATH.read_text())
    now = session_digest()
    diffs = describe_differences(golden, now)
    assert matches(golden, now), "per-frame outputs changed:\n" + "\n".join(diffs)
