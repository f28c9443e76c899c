"""The task's target: seeded, an object the task names uniquely when there is one."""

from grasp_pipeline.learning.targets import candidates, choose_target, is_ambiguous, task_phrase
from grasp_pipeline.sim.scene_spec import ObjectSpec

TEMPLATE = "pick up the {object} and put it in the tray"
RED, BLUE = (0.85, 0.15, 0.13, 1.0), (0.15, 0.35, 0.85, 1.0)


def _obj(name, kind, rgba):
    return ObjectSpec(name=name, kind=kind, size_m=(0.04, 0.04, 0.04), position_m=(0.5, 0.0, 0.22), rgba=rgba)


def test_a_task_names_an_object_no_other_object_shares_a_description_with():
    objs = [_obj("a", "cube", RED), _obj("b", "cube", RED), _obj("c", "cylinder", BLUE)]
    assert [o.name for o in candidates(objs, unique=True)] == ["c"]
    assert [o.name for o in candidates(objs, unique=False)] == ["a", "b", "c"]
    target, task = choose_target(objs, 3, TEMPLATE)
    assert target.name == "c" and task == "pick up the blue cylinder and put it in the tray"
    assert is_ambiguous(objs, objs[0]) and not is_ambiguous(objs, objs[2])


def test_the_choice_is_seeded():
    objs = [_obj(f"o{i}", "cube", rgba) for i, rgba in enumerate([RED, BLUE, (0.2, 0.65, 0.25, 1.0)])]
    picks = [choose_target(objs, s, TEMPLATE)[0].name for s in range(30)]
    assert picks == [choose_target(objs, s, TEMPLATE)[0].name for s in range(30)]
    assert len(set(picks)) == 3


def test_task_phrase_reads_the_object_back():
    assert task_phrase("pick up the red mug and put it in the tray", TEMPLATE) == "red mug"
    assert task_phrase("stack the blocks", TEMPLATE) == "stack the blocks"
