"""Names of a package loaded on first use: the one lazy-loading mechanism of lfdkit.

A package whose submodules import heavy dependencies (matplotlib, MuJoCo,
Starlette) can still list their names at its top: ``__getattr__, __dir__ =
lazy_names(__name__, {"name": "submodule", ...}, globals())`` imports the
submodule the first time one of its names is looked up and keeps the name, so
``import lfdkit.tasks.sweeping`` stays fast and ``from lfdkit.tasks.sweeping
import run_demo`` works. Python's module ``__getattr__`` (PEP 562) is the whole
mechanism; nothing else in lfdkit defers an import this way.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from typing import Any

__all__ = ["lazy_names"]


def lazy_names(
    package: str, names: Mapping[str, str], namespace: dict[str, Any]
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """A package's ``__getattr__`` and ``__dir__`` that load ``names`` from their submodules.

    Parameters
    ----------
    package : str
        The package's ``__name__``.
    names : mapping of str to str
        Each lazily loaded name and the submodule of ``package`` that defines it.
    namespace : dict
        The package's ``globals()``: a name found is stored there, so it is looked
        up once.

    Returns
    -------
    (__getattr__, __dir__)
        To assign at the package's top level.
    """
    table = dict(names)

    def __getattr__(name: str) -> Any:
        if name not in table:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(f"{package}.{table[name]}"), name)
        namespace[name] = value
        return value

    def __dir__() -> list[str]:
        return sorted(set(namespace) | set(table))

    return __getattr__, __dir__
