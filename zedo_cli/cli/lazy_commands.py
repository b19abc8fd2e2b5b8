"""The `zedo` command table, loaded lazily: `zedo --help` lists every command from a static
table of names and one-line summaries, and a command's module (with what it imports: numpy,
pydantic, the analysis package, ...) is imported only when that command runs or shows its own
help (docs/lifting.md, "Start-up and large batches")."""

from __future__ import annotations

import importlib
from collections.abc import Callable, Iterator, Mapping, MutableMapping
from typing import Any, NamedTuple


class LazyCommand(NamedTuple):
    """Where a command's function is (`module` in zedo_cli.cli, `function` in it), and the first
    line of its docstring, shown in `zedo --help` (tests/cli/test_startup.py keeps the two equal)."""

    module: str
    function: str
    summary: str

    def load(self) -> Callable[..., Any]:
        """The command's function, importing its module."""
        return getattr(importlib.import_module(f"{__package__}.{self.module}"), self.function)


class LazyCommands(MutableMapping[str, Any]):
    """A click group's `commands`: the names of `panels` (panel title -> name -> LazyCommand), each
    turned into a click command by `convert(name, function, panel)` the first time it is looked up.
    Iterating, `in`, `len`, `summary` and `panel` import nothing."""

    def __init__(
        self, panels: Mapping[str, Mapping[str, LazyCommand]], convert: Callable[[str, Callable[..., Any], str], Any]
    ) -> None:
        self._table = {name: entry for entries in panels.values() for name, entry in entries.items()}
        self._panels = {name: title for title, entries in panels.items() for name in entries}
        self._convert = convert
        self._loaded: dict[str, Any] = {}

    def summary(self, name: str) -> str:
        """The one-line help of `name`, without importing it."""
        entry = self._table.get(name)
        return entry.summary if entry is not None else self[name].get_short_help_str(limit=300)

    def panel(self, name: str) -> str | None:
        """The panel of `zedo --help` that lists `name` (None: the group's default)."""
        title = self._panels.get(name)
        return title if title is not None else getattr(self[name], "rich_help_panel", None)

    def __getitem__(self, name: str) -> Any:
        if name not in self._loaded:
            entry = self._table[name]  # KeyError for a name that is no command: click's "no such command"
            self._loaded[name] = self._convert(name, entry.load(), self._panels[name])
        return self._loaded[name]

    def __setitem__(self, name: str, command: Any) -> None:  # click's add_command
        self._loaded[name] = command

    def __delitem__(self, name: str) -> None:
        if name not in self:
            raise KeyError(name)
        for table in (self._table, self._panels, self._loaded):
            table.pop(name, None)

    def __iter__(self) -> Iterator[str]:
        yield from self._table
        yield from (name for name in self._loaded if name not in self._table)

    def __len__(self) -> int:
        return len(self._table) + sum(name not in self._table for name in self._loaded)

    def __contains__(self, name: object) -> bool:
        return name in self._table or name in self._loaded
