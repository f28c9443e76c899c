"""All parameter sets of a command, with the command line's overrides.

Each parameter set is a typed dataclass loaded from ``config/<section>.yaml``
(:func:`grasp_pipeline.config.load_config`). A command asks for the sections it
uses; the user may override them with

- ``--config FILE``: a YAML mapping ``section: {name: value, ...}`` (sections not
  used by the command are still checked against their parameter set), and
- ``--set name=value`` (repeatable): ``section.name=value``, or a bare ``name``
  when exactly one of the command's sections has it.

Unknown sections and names are errors (:class:`ConfigError`) that list what is known.
"""

from __future__ import annotations

import dataclasses
import difflib
import importlib
from types import MappingProxyType
from typing import Any, Iterable, Mapping

from .config import build_config, load_config, parse_yaml, read_yaml, unknown_names
from .exceptions import ConfigError
from .messages import brief

#: The one registry of parameter sets: section name -> (module, dataclass name). The YAML
#: file is config/<section>.yaml; the module is imported only when the section is loaded.
SECTIONS: Mapping[str, tuple[str, str]] = MappingProxyType({
    "scene_filter": ("grasp_pipeline.perception.config", "SceneFilterConfig"),
    "obb": ("grasp_pipeline.perception.config", "ObbConfig"),
    "workspace": ("grasp_pipeline.perception.workspace", "WorkspaceConfig"),
    "volume": ("grasp_pipeline.perception.volume_config", "VolumeConfig"),
    "camera": ("grasp_pipeline.sim.config", "CameraConfig"),
    "depth_noise": ("grasp_pipeline.robot.depth_noise", "DepthNoiseConfig"),
    "sim": ("grasp_pipeline.sim.config", "SimConfig"),
    "clutter": ("grasp_pipeline.sim.clutter_config", "ClutterConfig"),
    "motion": ("grasp_pipeline.motion.config", "MotionConfig"),
    "scan": ("grasp_pipeline.orchestration.config", "ScanConfig"),
    "grasp": ("grasp_pipeline.orchestration.config", "GraspConfig"),
    "place": ("grasp_pipeline.orchestration.execution.place_config", "PlaceConfig"),
    "declutter": ("grasp_pipeline.orchestration.config", "DeclutterConfig"),
    "grasp_fit": ("grasp_pipeline.orchestration.config", "GraspFitConfig"),
    "grasp_sampler": ("grasp_pipeline.orchestration.grasping.config", "SamplerConfig"),
    "video": ("grasp_pipeline.report.config", "VideoConfig"),
    "language": ("grasp_pipeline.language.config", "LanguageConfig"),
    "rerun": ("grasp_pipeline.report.config", "RerunConfig"),
    "record": ("grasp_pipeline.dataset.config", "RecordConfig"),
    "grasp_bound": ("grasp_pipeline.evaluation.config", "GraspBoundConfig"),
    "env": ("grasp_pipeline.learning.config", "PickEnvConfig"),
    "train": ("grasp_pipeline.learning.config", "TrainConfig"),
})


def section_class(name: str) -> type:
    if not isinstance(name, str) or name not in SECTIONS:
        raise ConfigError(f"unknown config section {brief(name)}; known: {', '.join(sorted(SECTIONS))}")
    module, cls_name = SECTIONS[name]
    return getattr(importlib.import_module(module), cls_name)


def parse_set(items: Iterable[str]) -> list[tuple[str, Any]]:
    """``name=value`` strings -> (name, YAML-parsed value)."""
    out = []
    for item in items:
        if "=" not in item:
            raise ConfigError(f"--set {brief(item)}: expected name=value (e.g. --set scene_filter.band=0.02)")
        name, raw = item.split("=", 1)
        name = name.strip()
        if not name:
            raise ConfigError(f"--set {brief(item)}: empty parameter name")
        out.append((name, parse_yaml(raw, f"--set {brief(name)}")))
    return out


class Settings:
    """The loaded parameter sets of one command: ``settings.scene_filter`` etc."""

    def __init__(self, configs: Mapping[str, Any]):
        self._configs = dict(configs)

    def __getattr__(self, name: str) -> Any:
        try:
            return self._configs[name]
        except KeyError:
            raise AttributeError(f"no config section {name!r} loaded "
                                 f"(loaded: {', '.join(self._configs)})") from None

    def sections(self) -> list[str]:
        return list(self._configs)

    def as_dict(self) -> dict[str, dict[str, Any]]:
        """Plain values, e.g. for a run report."""
        return {k: dataclasses.asdict(v) for k, v in self._configs.items()}


def load_settings(sections: Iterable[str], config_file: str | None = None,
                  sets: Iterable[str] = ()) -> Settings:
    """Load ``sections`` with the overrides of ``--config FILE`` and ``--set``."""
    sections = list(sections)
    classes = {s: section_class(s) for s in sections}
    overrides: dict[str, dict[str, Any]] = {s: {} for s in sections}
    if config_file is not None:
        data = read_yaml(config_file)
        for sec, values in data.items():
            cls = section_class(sec)  # unknown section -> error
            if not isinstance(values, dict):
                raise ConfigError(f"{config_file}: section {sec!r} must be a mapping of name: value")
            names = [f.name for f in dataclasses.fields(cls)]
            unknown = sorted(str(k) for k in set(values) - set(names))
            if unknown:
                raise ConfigError(unknown_names(unknown, names, sec, str(config_file)))
            if sec in overrides:
                overrides[sec].update(values)
            else:  # not used by this command: still validate the names and values
                build_config(cls, {**read_defaults(sec), **values}, source=str(config_file), section=sec)
    for name, value in parse_set(sets):
        if "." in name:
            sec, key = name.split(".", 1)
            if sec not in classes:
                raise ConfigError(f"--set {brief(name)}: section {brief(sec)} is not used by this command "
                                  f"(its sections: {', '.join(sections)})")
        else:
            owners = [s for s, c in classes.items() if key_in(c, name)]
            if not owners:
                raise ConfigError(f"--set {brief(name)}: unknown parameter; {_suggest(name, classes)}")
            if len(owners) > 1:
                raise ConfigError(f"--set {brief(name)}: ambiguous, in {', '.join(owners)}; "
                                  f"write e.g. --set {owners[0]}.{name}=...")
            sec, key = owners[0], name
        overrides[sec][key] = value
    return Settings({s: load_config(classes[s], s, None, overrides[s]) for s in sections})


def _suggest(name: str, classes: Mapping[str, type]) -> str:
    """Close matches of an unknown parameter name, else where the names are listed."""
    known = {f.name: s for s, c in classes.items() for f in dataclasses.fields(c)}
    close = difflib.get_close_matches(name, list(known), n=3, cutoff=0.7)
    if close:
        return "did you mean " + " or ".join(f"{known[c]}.{c}" for c in close) + "?"
    return (f"the sections of this command are {', '.join(classes)}; each section's parameters are "
            "listed in its file config/<section>.yaml")


def key_in(cls: type, name: str) -> bool:
    return any(f.name == name for f in dataclasses.fields(cls))


def read_defaults(section: str) -> dict[str, Any]:
    from .assets import default_config_dir

    path = default_config_dir() / f"{section}.yaml"
    return read_yaml(path) if path.exists() else {}
