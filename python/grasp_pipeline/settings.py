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
import importlib
from types import MappingProxyType
from typing import Any, Iterable, Mapping

import yaml

from .config import build_config, load_config, read_yaml
from .exceptions import ConfigError

#: The one registry of parameter sets: section name -> (module, dataclass name). The YAML
#: file is config/<section>.yaml; the module is imported only when the section is loaded.
SECTIONS: Mapping[str, tuple[str, str]] = MappingProxyType({
    "scene_filter": ("grasp_pipeline.perception.config", "SceneFilterConfig"),
    "obb": ("grasp_pipeline.perception.config", "ObbConfig"),
    "workspace": ("grasp_pipeline.perception.workspace", "WorkspaceConfig"),
    "camera": ("grasp_pipeline.sim.config", "CameraConfig"),
    "sim": ("grasp_pipeline.sim.config", "SimConfig"),
    "clutter": ("grasp_pipeline.sim.clutter_config", "ClutterConfig"),
    "motion": ("grasp_pipeline.motion.config", "MotionConfig"),
    "scan": ("grasp_pipeline.orchestration.config", "ScanConfig"),
    "grasp": ("grasp_pipeline.orchestration.config", "GraspConfig"),
    "declutter": ("grasp_pipeline.orchestration.config", "DeclutterConfig"),
    "grasp_fit": ("grasp_pipeline.orchestration.config", "GraspFitConfig"),
    "video": ("grasp_pipeline.report.config", "VideoConfig"),
    "language": ("grasp_pipeline.language.config", "LanguageConfig"),
    "rerun": ("grasp_pipeline.report.config", "RerunConfig"),
    "record": ("grasp_pipeline.dataset.config", "RecordConfig"),
    "env": ("grasp_pipeline.learning.config", "PickEnvConfig"),
    "train": ("grasp_pipeline.learning.config", "TrainConfig"),
})


def section_class(name: str) -> type:
    if name not in SECTIONS:
        raise ConfigError(f"unknown config section {name!r}; known: {', '.join(sorted(SECTIONS))}")
    module, cls_name = SECTIONS[name]
    return getattr(importlib.import_module(module), cls_name)


def parse_set(items: Iterable[str]) -> list[tuple[str, Any]]:
    """``name=value`` strings -> (name, YAML-parsed value)."""
    out = []
    for item in items:
        if "=" not in item:
            raise ConfigError(f"--set {item!r}: expected name=value (e.g. --set scene_filter.band=0.02)")
        name, raw = item.split("=", 1)
        name = name.strip()
        if not name:
            raise ConfigError(f"--set {item!r}: empty parameter name")
        try:
            value = yaml.safe_load(raw)
        except yaml.YAMLError as exc:
            raise ConfigError(f"--set {item!r}: cannot parse the value ({exc})") from None
        out.append((name, value))
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
            unknown = sorted(set(values) - {f.name for f in dataclasses.fields(cls)})
            if unknown:
                raise ConfigError(f"{config_file}: unknown parameter(s) {', '.join(unknown)} in section "
                                  f"{sec!r}; known: {', '.join(sorted(f.name for f in dataclasses.fields(cls)))}")
            if sec in overrides:
                overrides[sec].update(values)
            else:  # not used by this command: still validate the names and values
                build_config(cls, {**read_defaults(sec), **values}, source=str(config_file))
    for name, value in parse_set(sets):
        if "." in name:
            sec, key = name.split(".", 1)
            if sec not in classes:
                raise ConfigError(f"--set {name}: section {sec!r} is not used by this command "
                                  f"(its sections: {', '.join(sections)})")
        else:
            owners = [s for s, c in classes.items() if key_in(c, name)]
            if not owners:
                known = {s: sorted(f.name for f in dataclasses.fields(c)) for s, c in classes.items()}
                raise ConfigError(f"--set {name}: unknown parameter; known: "
                                  + "; ".join(f"{s}: {', '.join(v)}" for s, v in known.items()))
            if len(owners) > 1:
                raise ConfigError(f"--set {name}: ambiguous, in {', '.join(owners)}; "
                                  f"write e.g. --set {owners[0]}.{name}=...")
            sec, key = owners[0], name
        overrides[sec][key] = value
    return Settings({s: load_config(classes[s], s, None, overrides[s]) for s in sections})


def key_in(cls: type, name: str) -> bool:
    return any(f.name == name for f in dataclasses.fields(cls))


def read_defaults(section: str) -> dict[str, Any]:
    from .assets import default_config_dir

    path = default_config_dir() / f"{section}.yaml"
    return read_yaml(path) if path.exists() else {}
