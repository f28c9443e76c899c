"""Readable error messages: values and texts cut to what a terminal line can show.

A value from the user (a ``--set`` string, a YAML value that expands to millions of items)
must never make an error message megabytes long, nor take minutes to print:

* :func:`brief` is the ``repr`` of a value, cut (``reprlib`` stops at a few items per level and
  a few levels, so it costs the same for a huge value as for a small one);
* :func:`shorten` cuts a finished message, saying how much was left out.
"""

from __future__ import annotations

import reprlib

#: Longest value shown in a message [characters].
MAX_VALUE_CHARS = 80
#: Longest message the command line prints [characters].
MAX_MESSAGE_CHARS = 1000

_REPR = reprlib.Repr()
_REPR.maxlevel = 3
_REPR.maxlist = _REPR.maxtuple = _REPR.maxset = _REPR.maxdict = 6
_REPR.maxstring = _REPR.maxother = _REPR.maxlong = MAX_VALUE_CHARS


def brief(value: object, limit: int = MAX_VALUE_CHARS) -> str:
    """``repr(value)`` of at most about ``limit`` characters."""
    return shorten(_REPR.repr(value), limit)


def shorten(text: str, limit: int = MAX_MESSAGE_CHARS) -> str:
    """``text`` itself when short enough, else its start and how many characters were cut."""
    text = str(text)
    if len(text) <= limit:
        return text
    keep = max(limit - 30, 10)
    return f"{text[:keep]}... ({len(text) - keep} more characters)"


def name(text: object) -> str:
    """A name from the user as typed when it is a plain identifier, else quoted and cut."""
    return text if isinstance(text, str) and text.isidentifier() else brief(text, 40)
