"""The built-in object set as a sequence whose objects are built when first asked for.

A packed or pile scene draws a handful of objects from the set by index, so building all of
them (a third of a second: the mugs' and bowls' convex parts) is mostly wasted in a process
that runs one scene. :class:`BuiltinSet` holds the names and builds an object at its first
access; each object is built once per process and every set gets its own copies (callers may
modify them, as those of a loaded list).
"""

from __future__ import annotations

import copy
from collections.abc import Sequence
from typing import overload

from .model import ObjectModel

#: Objects built in this process, by name (the originals: sets hand out copies).
_BUILT: dict[str, ObjectModel] = {}


def _built(name: str) -> ObjectModel:
    model = _BUILT.get(name)
    if model is None:
        from .builtin import builtin_object

        model = _BUILT[name] = builtin_object(name)
    return model


class BuiltinSet(Sequence):
    """The built-in objects in the order of ``BUILTIN_NAMES``, built on first access
    (``len`` and ``names`` build nothing); indexing and iterating as a list of
    :class:`~.model.ObjectModel`, the same object for the same index."""

    def __init__(self) -> None:
        from .builtin import BUILTIN_NAMES

        self.names: tuple[str, ...] = tuple(BUILTIN_NAMES)
        self._copies: dict[int, ObjectModel] = {}

    def __len__(self) -> int:
        return len(self.names)

    @overload
    def __getitem__(self, index: int) -> ObjectModel: ...
    @overload
    def __getitem__(self, index: slice) -> list[ObjectModel]: ...

    def __getitem__(self, index):
        if isinstance(index, slice):
            return [self[k] for k in range(*index.indices(len(self)))]
        k = range(len(self.names))[index]  # a list's IndexError, negative indices
        model = self._copies.get(k)
        if model is None:
            model = self._copies[k] = copy.deepcopy(_built(self.names[k]))
        return model

    def __repr__(self) -> str:
        return f"BuiltinSet({len(self)} objects, {len(self._copies)} built)"
