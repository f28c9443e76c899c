"""Errors of the language resolver: a description it cannot read, or one that names no
object or more than one of the objects seen."""

from __future__ import annotations

from ..exceptions import GraspPipelineError, InputError


class LanguageError(GraspPipelineError):
    """Base of the resolver's refusals."""


class DescriptionError(LanguageError, InputError):
    """The description cannot be read: it names nothing, or two values of one attribute."""


class UnknownWordError(DescriptionError):
    """The description uses a word outside the vocabulary (the message lists the vocabulary)."""


class NoMatchError(LanguageError):
    """No perceived object fits the description (the message lists what was seen)."""


class AmbiguousDescriptionError(LanguageError):
    """More than one perceived object fits the description (the message lists them)."""


class SameObjectError(LanguageError):
    """Two descriptions of one run name the same perceived object (it can be picked once)."""
