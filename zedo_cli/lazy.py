"""Package exports that load on first use (PEP 562), so importing a package stays cheap.

`zedo --help` and `import zedo_cli` must not pay for torch or matplotlib; a subpackage's
`__init__` lists its public names with `lazy_exports` instead of importing its modules.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Iterable
from typing import Any


def lazy_exports(
    package: str, namespace: dict[str, Any], exports: dict[str, Iterable[str]]
) -> tuple[Callable[[str], Any], Callable[[], list[str]], list[str]]:
    """`__getattr__`, `__dir__` and `__all__` for `package`, whose public names are given as
    {relative module: names}; a name's module is imported when the name is first looked up."""
    origin = {name: module for module, names in exports.items() for name in names}

    def __getattr__(name: str) -> Any:
        if name not in origin:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(origin[name], package), name)
        namespace[name] = value  # later look-ups skip this function
        return value

    def __dir__() -> list[str]:
        return sorted(set(namespace) | set(origin))

    return __getattr__, __dir__, sorted(origin)
