"""`--config FILE`: a command's settings from a TOML file, and `--print-config`'s TOML.

A file holds a table per command, each option by its long name (dashes or underscores alike)::

    [lift]
    steps = 30
    seed = 3
    focal = 1500

    [analyze]
    symmetry-threshold = 30

A command reads its own table; the tables of other zedo commands are left to them (a note says
so). An unknown option (with the nearest real one as a hint), a value of the wrong type or out of
range, a table that is no command or a file that is not TOML is one line naming the file and the
key (`ConfigError`, exit code 2). A zedo result (.zedo.json / .jsonl) is a `zedo lift` config too:
its recorded settings (`settings.from_result`). Paths in a file are read as on the command line,
from the working directory.
"""

from __future__ import annotations

import difflib
import json
import math
import tomllib
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pydantic import ValidationError

from ..errors import ConfigError
from .model import Options, show


@dataclass(frozen=True)
class ConfigFile:
    """What a --config file gives one command."""

    path: str
    values: dict[str, Any]  # option key -> value, each checked against the command's model
    notes: tuple[str, ...] = ()  # tables left to other commands
    prior_sha256: str | None = None  # a result: the prior it was lifted with (checked when the prior loads)
    needs: dict[str, str] = field(default_factory=dict)  # option key -> why it must be given on the command line


def did_you_mean(word: str, choices: Iterable[str]) -> str | None:
    close = difflib.get_close_matches(word, list(choices), n=1, cutoff=0.6)
    return close[0] if close else None


def read_toml_config(name: str, model: type[Options], commands: Iterable[str] = ()) -> ConfigFile:
    """The values `model.command`'s table of the TOML file `name` gives; `commands`: every zedo
    command, whose tables are left alone."""
    try:
        doc = tomllib.loads(Path(name).read_text(encoding="utf-8"))
    except OSError as exc:
        raise ConfigError(f"{name}: cannot read the --config file ({exc.strerror or exc})") from None
    except UnicodeDecodeError:
        raise ConfigError(f"{name}: not a TOML file (not UTF-8 text)") from None
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{name}: not a TOML file: {exc}") from None
    command, notes = model.command, []
    for table, content in doc.items():
        if not isinstance(content, dict):
            raise ConfigError(f"{name}: {table}: options go in a table per command, e.g. [{command}] then "
                              f"{table} = ...")  # fmt: skip
        if table == command:
            continue
        if table in commands:
            notes.append(f"{name}: [{table}] is for zedo {table}; zedo {command} reads [{command}]")
            continue
        close = did_you_mean(table, [*commands, command])
        hint = f"; did you mean [{close}]?" if close else f" (a table is named after a command, e.g. [{command}])"
        raise ConfigError(f"{name}: [{table}]: no zedo command of that name{hint}")
    values = table_values(name, doc.get(command, {}), model)
    return ConfigFile(name, values, tuple(notes))


def table_values(name: str, table: dict[str, Any], model: type[Options]) -> dict[str, Any]:
    """A table's options by key (dashes read as underscores), every one checked against `model`."""
    command, keys = model.command, model.keys()
    values: dict[str, Any] = {}
    for raw, value in table.items():
        key = raw.replace("-", "_")
        if key not in keys:
            close = did_you_mean(key, keys)
            hint = f"; did you mean {close}?" if close else f" (zedo {command} --help lists them)"
            raise ConfigError(f"{name}: [{command}] {raw}: no such option of zedo {command}{hint}")
        if key in values:
            raise ConfigError(f"{name}: [{command}] {raw}: given twice (as {key} too)")
        values[key] = value
    check_values(name, values, model)
    return values


def check_values(name: str, values: dict[str, Any], model: type[Options]) -> None:
    """Each value of `values` of its option's type and range (the options left out are not looked at)."""
    try:
        model.model_validate(values)
    except ValidationError as exc:
        for err in exc.errors():
            key = model.key_of(err["loc"][0]) if err["loc"] else ""
            if key in values:
                raise ConfigError(f"{name}: [{model.command}] {key}: expected {model.expected(key)}, "
                                  f"got {show(values[key])}") from None  # fmt: skip


def toml_value(value: Any) -> str:
    """One value in TOML: a string, a number, a boolean or an array of numbers."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            return "nan" if value != value else ("inf" if value > 0 else "-inf")
        return repr(value)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    # a TOML basic string: JSON's escapes are TOML's, and DEL must be escaped too
    return json.dumps(str(value), ensure_ascii=False).replace("\x7f", "\\u007f")


def config_toml(options: Options, source: str | None = None) -> str:
    """`options` as the command's table of a TOML file that --config reads back to the same
    settings; options without a value (their default is none) are commented out."""
    command = options.command
    lines = [f"# zedo {command}: the settings in effect (defaults < --config {source or 'FILE'} < the command line)",
             f"# zedo {command} --help says what each one does.", f"[{command}]"]  # fmt: skip
    for key, value in options.values().items():
        lines.append(f"# {key} =  (not set)" if value is None else f"{key} = {toml_value(value)}")
    return "\n".join(lines) + "\n"
