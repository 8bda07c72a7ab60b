"""Lazy re-exports for subpackage ``__init__`` modules (PEP 562): nothing imported until used.

Each subpackage names its public API once, as ``{name: submodule}``; the submodule is imported
on first access of one of its names, so ``import ik7r`` and the one-shot command line stay fast
(importing a compiled-kernel module imports numba).
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable
from typing import Any


def lazy_exports(package: str, exports: dict[str, str],
                 modules: tuple[str, ...] = ()) -> tuple[Callable[[str], Any], Callable[[], list]]:
    """``(__getattr__, __dir__)`` for ``package``.

    ``exports`` maps each public name to the submodule that defines it; ``modules`` names
    submodules exported as modules themselves.
    """

    def __getattr__(name: str):
        if name in modules:
            return importlib.import_module(f"{package}.{name}")
        module = exports.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(f"{package}.{module}"), name)
        setattr(sys.modules[package], name, value)  # found directly from now on
        return value

    def __dir__() -> list:
        return sorted({*vars(sys.modules[package]), *exports, *modules})

    return __getattr__, __dir__
