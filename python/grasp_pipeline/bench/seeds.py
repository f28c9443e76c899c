"""The scene seeds of the benchmarks' scenes and rounds (also ``record`` and ``eval``): a
benchmark seed and an index give one scene seed, reproduced alone with ``grasp-pipeline run
--seed <scene seed>``."""

from __future__ import annotations

import numpy as np

#: How :func:`scene_seed` derives a scene seed (written into the results).
SCENE_SEED_RULE = "numpy SeedSequence(entropy=seed, spawn_key=(index,)) -> uint32 >> 1"


def scene_seed(seed: int, index: int) -> int:
    """The random-scene seed of scene ``index`` of a benchmark with seed ``seed``.

    Derived with numpy's ``SeedSequence`` (a stable, documented hash), so benchmarks with
    different seeds draw independent scenes; a non-negative 31-bit integer.
    """
    state = np.random.SeedSequence(entropy=int(seed), spawn_key=(int(index),)).generate_state(1, np.uint32)
    return int(state[0] >> 1)
