"""`--config FILE` read for one command: a TOML file (`config_file`) or a zedo result (`from_result`)."""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

from .config_file import ConfigFile, read_toml_config
from .from_result import result_config
from .model import Options

RESULT_SUFFIXES = (".json", ".jsonl", ".ndjson")  # a zedo result: a config of zedo lift


def read_config(path: str | Path, model: type[Options], commands: Iterable[str] = ()) -> ConfigFile:
    """What the --config file `path` gives the command of `model`: its table of a TOML file, or
    the settings a zedo result records; `commands`: every zedo command (their tables are left alone)."""
    name = str(path)
    if Path(name).suffix.lower() in RESULT_SUFFIXES:
        return result_config(name, model)
    return read_toml_config(name, model, commands)
