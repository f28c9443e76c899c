"""Bad input refused before anything is simulated or trained, with a one-line reason:

* :func:`check_dataset` — a ``train --dataset`` folder that is missing, not a LeRobot dataset,
  a ``record`` output left incomplete, or recorded with other features than the environment's
  (other image sizes, rate, depth: the message says which option matches it);
* :func:`policy_config` — an ``eval --policy`` folder that is missing or not a policy saved by
  LeRobot (``save_pretrained``, with its pre/post-processors);
* :func:`check_policy_features` — a policy whose input features the environment does not give
  (a missing key, or another shape), or whose action is not the environment's.
"""

from __future__ import annotations

import json
from pathlib import Path

from ..exceptions import InputError

#: Files a LeRobot policy folder holds (``save_pretrained`` of the policy and its processors).
POLICY_FILES = ("config.json", "model.safetensors", "policy_preprocessor.json", "policy_postprocessor.json")


def _shape(ft) -> tuple:
    return tuple(int(s) for s in (ft["shape"] if isinstance(ft, dict) else ft.shape))


def _hint(key: str, want: tuple) -> str:
    if key.startswith("observation.images.") and len(want) == 3:
        side = want[0] if want[-1] == 3 else want[-1]
        return f" (images of {side} px: --image-size {side})"
    if key.startswith("observation.depth."):
        return " (depth images: --depth)"
    return ""


def check_dataset(root, env_features: dict, fps: int):
    """The LeRobot metadata of the ``record`` dataset at ``root``; :class:`InputError` when it
    cannot be trained on for an environment with observations ``env_features`` (key -> feature)
    at ``fps``."""
    from ..dataset.dataset_folder import MARKER
    from ..dataset.lerobot_writer import require_lerobot

    root = Path(root)
    if not root.is_dir():
        raise InputError(f"--dataset {root}: no such folder")
    if (root / MARKER).is_file():
        marker = json.loads((root / MARKER).read_text())
        raise InputError(f"--dataset {root} is an incomplete record output ({marker.get('reason', '')}); "
                         "record it again or choose a complete dataset")
    if not (root / "meta" / "info.json").is_file():
        raise InputError(f"--dataset {root} is not a LeRobot dataset (no meta/info.json)")
    require_lerobot()
    from lerobot.datasets.lerobot_dataset import LeRobotDatasetMetadata

    meta = LeRobotDatasetMetadata(json.loads((root / "meta/info.json").read_text()).get("repo_id") or
                                  "grasp_pipeline/picks", root=root)
    for key, ft in env_features.items():
        have = meta.features.get(key)
        if have is None:
            raise InputError(f"--dataset {root} has no {key!r} {_shape(ft)}{_hint(key, _shape(ft))}: "
                             "it was not recorded by grasp-pipeline record with these options")
        if _shape(have) != _shape(ft):
            raise InputError(f"--dataset {root} was recorded with {key} {_shape(have)}, the environment "
                             f"gives {_shape(ft)}: use the recording's options{_hint(key, _shape(have))}")
    if int(meta.fps) != int(fps):
        raise InputError(f"--dataset {root} was recorded at {meta.fps} fps, the environment runs at "
                         f"{fps}: use --fps {meta.fps}")
    return meta


def policy_config(path):
    """The LeRobot config of the policy saved at ``path`` (see the module doc)."""
    path = Path(path)
    if not path.is_dir():
        raise InputError(f"--policy {path}: no such folder (a policy saved by LeRobot's save_pretrained, "
                         "or 'reference')")
    missing = [f for f in POLICY_FILES if not (path / f).is_file()]
    if missing:
        raise InputError(f"--policy {path} is not a LeRobot policy saved with its processors "
                         f"(missing {', '.join(missing)})")
    from lerobot.configs.policies import PreTrainedConfig

    import lerobot.policies  # noqa: F401  (registers the policy types)

    try:
        return PreTrainedConfig.from_pretrained(str(path))
    except Exception as exc:  # draccus: an unknown type, a malformed file
        raise InputError(f"--policy {path}: config.json is not a LeRobot policy config "
                         f"({type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''})") from None


def check_policy_features(cfg, observation_space, action_space, where: str = "--policy") -> None:
    """:class:`InputError` naming the first input the environment does not give as the policy
    expects it (key and shapes), or an action of another size."""
    spaces = observation_space.spaces
    for key, ft in (cfg.input_features or {}).items():
        want = _shape(ft)
        if key not in spaces:
            raise InputError(f"{where}: the policy's input {key} {want} is not an observation of the "
                             f"environment (it gives {', '.join(sorted(spaces))}){_hint(key, want)}")
        have = tuple(spaces[key].shape)
        if len(want) == 3 and len(have) == 3:
            have = (have[2], have[0], have[1])  # the policy sees images channel first
        if have != want:
            raise InputError(f"{where}: the policy's input {key} is {want}, the environment gives "
                             f"{have}{_hint(key, want)}")
    action = (cfg.output_features or {}).get("action")
    if action is None or _shape(action) != tuple(action_space.shape):
        got = None if action is None else _shape(action)
        raise InputError(f"{where}: the policy's action is {got}, the environment's is "
                         f"{tuple(action_space.shape)} (7 joint targets and a finger gap)")
