"""Package attributes that load their module on first use (PEP 562, D-173).

A package that names its public objects in ``__all__`` and where each one lives in
``where`` gets a module ``__getattr__`` that imports the module when the name is first read
(and keeps the value, so the import happens once) and a ``__dir__`` that lists the names
before they load: ``--help`` and ``check`` stay fast, the runtime loads only when used.
"""

from __future__ import annotations

import importlib
import sys
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from collections.abc import Callable, Mapping, Sequence


def lazy_exports(package: str, where: Mapping[str, str], names: Sequence[str]
                 ) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """``__getattr__`` and ``__dir__`` for ``package`` (its ``__name__``)."""
    namespace = sys.modules[package].__dict__

    def __getattr__(name: str) -> Any:  # noqa: N807 - the module hook's name
        module = where.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(module), name)
        namespace[name] = value
        return value

    def __dir__() -> list[str]:  # noqa: N807 - the module hook's name
        return sorted(set(namespace) | set(names))

    return __getattr__, __dir__
