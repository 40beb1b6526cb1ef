"""Old import paths of names that moved: a module ``__getattr__`` that finds them where they are.

A module whose contents moved keeps its name for old imports with
``__getattr__ = moved(__name__, "new.module", names)``: each of ``names`` is
looked up in the new module on first use, with a :class:`DeprecationWarning`
naming the new place. The new module is imported only then, never when the
old one is, so a lower layer may keep an old name of something that moved to
a higher one without importing it.
"""

from __future__ import annotations

import importlib
import sys
import warnings
from collections.abc import Callable, Iterable
from typing import Any

__all__ = ["moved"]


def moved(old: str, new: str, names: Iterable[str]) -> Callable[[str], Any]:
    """A module ``__getattr__`` for module ``old`` that forwards ``names`` to module ``new``."""
    forwarded = frozenset(names)

    def __getattr__(name: str) -> Any:
        if name not in forwarded:
            raise AttributeError(f"module {old!r} has no attribute {name!r}")
        warnings.warn(
            f"{old}.{name} moved to {new}.{name}; import it from there",
            DeprecationWarning,
            stacklevel=2,
        )
        value = getattr(importlib.import_module(new), name)
        setattr(sys.modules[old], name, value)  # found: warned once, not again
        return value

    return __getattr__
