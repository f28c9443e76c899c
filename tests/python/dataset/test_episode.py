"""An episode's frames fit the dataset's features."""

import numpy as np
import pytest

from grasp_pipeline.config import build_config
from grasp_pipeline.dataset.config import RecordConfig
from grasp_pipeline.dataset.episode import Episode
from grasp_pipeline.dataset.features import dataset_features, frame_values
from grasp_pipeline.exceptions import ConfigError


def _episode(n=5, success=True):
    rng = np.random.default_rng(0)
    f = lambda k: rng.random((n, k), dtype=np.float32)  # noqa: E731
    return Episode(task="pick up the cube and put it in the tray", success=success,
                   failed_stage="" if success else "CLOSE", message="m", object="cube_0",
                   time_s=np.arange(n) / 15.0, state=f(8), ee_pose=f(7), action=f(8), action_ee_delta=f(7),
                   images={c: rng.integers(0, 255, (n, 16, 16, 3), dtype=np.uint8) for c in ("wrist", "scene")},
                   depths={c: rng.random((n, 16, 16), dtype=np.float32) for c in ("wrist", "scene")})


@pytest.mark.parametrize("depth", [False, True])
def test_frames_match_the_features(depth):
    cfg = build_config(RecordConfig, {"image_width_px": 16, "image_height_px": 16, "use_videos": False})
    feats = dataset_features(cfg, depth)
    ep = _episode(success=False)
    frames = [frame_values(ep, i, depth) for i in range(ep.length)]
    for fr in frames:
        assert set(fr) - {"task"} == set(feats)
        for k, ft in feats.items():
            if ft["dtype"] in ("video", "image", "float32", "bool"):
                assert tuple(np.shape(fr[k])) == tuple(ft["shape"]), k
    assert [bool(f["next.done"][0]) for f in frames] == [False] * 4 + [True]
    assert not any(bool(f["next.success"][0]) for f in frames)      # a failed episode
    assert {f["episode.failed_stage"] for f in frames} == {"CLOSE"}


@pytest.mark.parametrize("values", [{"record_fps_hz": 0}, {"image_width_px": 255}, {"image_height_px": 24},
                                    {"task_template": "pick it"}, {"repo_id": "picks"}])
def test_bad_record_config_is_refused(values):
    with pytest.raises(ConfigError):
        build_config(RecordConfig, values)
