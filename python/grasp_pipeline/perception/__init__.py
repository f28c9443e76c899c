"""Perception: the C++ core's per-frame path (scene filter, estimates, tracker).

``PerceptionSession`` is the entry point; the fine-grained functions live in
``grasp_pipeline._core`` (see ``_core.pyi``).
"""

from .config import ObbConfig, SceneFilterConfig, load_obb_config, load_scene_filter_config
from .session import FrameResult, PerceptionSession

__all__ = [
    "FrameResult",
    "ObbConfig",
    "PerceptionSession",
    "SceneFilterConfig",
    "load_obb_config",
    "load_scene_filter_config",
]
