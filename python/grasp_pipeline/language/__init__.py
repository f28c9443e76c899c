"""Picks selected by language: name perceived objects and resolve short descriptions.

>>> from grasp_pipeline.language import resolve, describe, colour_name
>>> colour_name((0.85, 0.15, 0.13))
'red'
"""

from .attributes import PerceivedObject, perceive_objects, perceived_object, relative_sizes
from .colours import colour_name, object_colour
from .config import LanguageConfig
from .exceptions import (AmbiguousDescriptionError, DescriptionError, LanguageError, NoMatchError,
                         SameObjectError, UnknownWordError)
from .observations import ObservationRecorder
from .parse import Wanted, parse
from .picks import resolve_picks
from .resolver import describe, resolve

__all__ = ["AmbiguousDescriptionError", "DescriptionError", "LanguageConfig", "LanguageError",
           "NoMatchError", "ObservationRecorder", "PerceivedObject", "SameObjectError",
           "UnknownWordError", "Wanted",
           "colour_name", "describe", "object_colour", "parse", "perceive_objects",
           "perceived_object", "relative_sizes", "resolve", "resolve_picks"]
