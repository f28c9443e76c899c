"""The grasp sources ``grasp.grasp_source`` names (orchestration/grasping/registry.py): the
built-in ones, a source registered from outside the package, bad names."""

import pytest

from grasp_pipeline.exceptions import ConfigError
from grasp_pipeline.orchestration import FixedGraspSource, GeometricGraspSource, GraspSource
from grasp_pipeline.orchestration.grasping import registry, source_names
from grasp_pipeline.orchestration.grasping.any_side import AnySideGraspSource
from grasp_pipeline.settings import SECTIONS, load_settings


def _settings(*sets: str):
    return load_settings(sorted(SECTIONS), sets=sets)


def test_the_built_in_sources_are_selected_by_name():
    assert registry.grasp_source_names() == ("any_side", "top_down") == source_names.BUILT_IN
    assert tuple(registry._FACTORIES) == source_names.BUILT_IN  # each built-in name has its factory
    assert isinstance(registry.make_grasp_source(_settings()), AnySideGraspSource)  # the default
    source = registry.make_grasp_source(_settings("grasp.grasp_source=top_down"))
    assert isinstance(source, GeometricGraspSource) and isinstance(source, GraspSource)


def test_a_registered_source_can_be_named_in_the_settings(monkeypatch):
    monkeypatch.setattr(registry, "_FACTORIES", dict(registry._FACTORIES))
    monkeypatch.setattr(source_names, "_added", [])
    registry.register_grasp_source("known_poses", lambda settings: FixedGraspSource([]))
    source = registry.make_grasp_source(_settings("grasp.grasp_source=known_poses"))
    assert isinstance(source, FixedGraspSource)
    with pytest.raises(ValueError, match="already registered"):
        registry.register_grasp_source("known_poses", lambda settings: FixedGraspSource([]))


@pytest.mark.parametrize("name", ["", "Learned", "my-grasps", "2nd"])
def test_a_bad_source_name_is_refused(name):
    with pytest.raises(ValueError, match="lower-case"):
        registry.register_grasp_source(name, lambda settings: FixedGraspSource([]))


def test_an_unknown_source_in_the_settings_names_the_known_ones():
    with pytest.raises(ConfigError, match="expected one of any_side, top_down"):
        _settings("grasp.grasp_source=learned")
