"""The object an episode's task names, and the task sentence.

The environment chooses the target at reset, with a generator seeded by the scene seed: one
of the scene's objects, among those whose description ("red mug": colour and category, as
``record`` words its tasks, :mod:`grasp_pipeline.dataset.tasks`) no other object of the scene
shares when ``unique`` and there is such an object — a task names one object.
"""

from __future__ import annotations

import re
from collections import Counter

import numpy as np

from ..dataset.tasks import object_phrase, task_text

#: Stream of the seed's generator that draws the target (the scene itself uses the seed).
TARGET_STREAM = 1


def candidates(objects, unique: bool) -> list:
    """The objects a task may name."""
    objects = list(objects)
    if not unique:
        return objects
    counts = Counter(object_phrase(o) for o in objects)
    named = [o for o in objects if counts[object_phrase(o)] == 1]
    return named or objects


def choose_target(objects, seed: int, template: str, unique: bool = True):
    """(target object, task sentence) for the scene of ``seed``; ``template`` holds
    ``{object}`` (``record.yaml`` ``task_template``)."""
    cands = candidates(objects, unique)
    if not cands:
        raise ValueError("the scene has no objects to name in a task")
    rng = np.random.default_rng([int(seed), TARGET_STREAM])
    target = cands[int(rng.integers(len(cands)))]
    return target, task_text(template, target)


def is_ambiguous(objects, target) -> bool:
    """True when another object of the scene has the target's description."""
    phrase = object_phrase(target)
    return sum(object_phrase(o) == phrase for o in objects) > 1


def task_phrase(task: str, template: str) -> str:
    """The object phrase of a task sentence worded by ``template`` ("red mug"); the whole
    sentence when it is not worded so."""
    pattern = re.escape(template).replace(re.escape("{object}"), "(.+)")
    m = re.fullmatch(pattern, task.strip())
    return m.group(1) if m else task
