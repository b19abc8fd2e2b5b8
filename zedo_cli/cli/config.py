"""`--config FILE` and `--print-config` of `zedo lift`, `analyze`, `render`, `calibrate`, `norms`, `export`,
`adapt`, `fit-prior`, `fit-augmenter`, `augment`, `evaluate`, `benchmark` and `benchmark-symmetry`.

Precedence: a command's defaults < its table of the --config file < the flags given on the
command line. The file is read before click parses the command line (`ZedoCommand.parse_args`)
and its values become click's `default_map`, so a flag given wins and a required option may come
from the file; the command then builds its settings model (`settings.*Options`) from every
option's value (`resolve_options`), which --print-config prints as TOML.
"""

from __future__ import annotations

import importlib
import sys
from dataclasses import dataclass
from typing import Any

import typer

from ..errors import ConfigError, ZedoError, one_line
from ..settings.config import read_config
from ..settings.config_file import ConfigFile, config_toml
from ..settings.model import Options

try:  # typer >= 0.2x vendors click as typer._click; older versions use click itself
    from typer._click.core import ParameterSource  # type: ignore[import-not-found]
    from typer._click.globals import get_current_context  # type: ignore[import-not-found]
except ImportError:  # pragma: no cover
    from click.core import ParameterSource  # type: ignore[no-redef]
    from click.globals import get_current_context  # type: ignore[no-redef]

META = "zedo.config"  # ctx.meta's key of the ConfigFile read
PANEL = "Settings files"
# The command -> its settings model (module in zedo_cli.settings, class), imported when a --config is read.
MODELS = {
    "lift": ("lift", "LiftOptions"),
    "analyze": ("analyze", "AnalyzeOptions"),
    "render": ("render", "RenderOptions"),
    "calibrate": ("calibrate", "CalibrateOptions"),
    "norms": ("norms", "NormsOptions"),
    "export": ("export", "ExportOptions"),
    "adapt": ("adapt", "AdaptOptions"),
    "fit-prior": ("fit_prior", "FitPriorOptions"),
    "fit-augmenter": ("augment", "FitAugmenterOptions"),
    "augment": ("augment", "AugmentOptions"),
    "evaluate": ("evaluate", "EvaluateOptions"),
    "benchmark": ("evaluate", "BenchmarkOptions"),
    "benchmark-symmetry": ("evaluate", "BenchmarkSymmetryOptions"),
}
CONFIG_HELP = (
    "Settings from a TOML file: its [{command}] table, options by their long names ({example}); "
    'flags given here win (docs/cli.md, "Config files").{result}'
)
EXAMPLES = {
    "lift": "steps = 30",
    "analyze": "fps = 30.0",
    "render": "side-view = true",
    "calibrate": "square = 0.025",
    "norms": "age-weeks = [8.0]",
    "export": 'marker-axes = "overhead"',
    "adapt": 'strategy = "finetune"',
    "fit-prior": "epochs = 2000",
    "fit-augmenter": "epochs = 16",
    "augment": "strength = 0.3",
    "evaluate": 'protocol = "h36m17"',
    "benchmark": 'preset = ["fast"]',
    "benchmark-symmetry": "symmetry-threshold = 30.0",
}
PRINT_CONFIG_HELP = "Print the settings in effect as TOML (a --config file) and exit."


def model_option(model: type[Options], key: str, *names: str, **extra: Any) -> Any:
    """A typer option of `model`'s field `key`, with the model's help text (one source for the command line,
    --config and the Python API)."""
    return typer.Option(*names, help=model.help(key), **extra)


def config_option(command: str, panel: str | None = None) -> Any:
    result = " A zedo result lifts again with its recorded settings." if command == "lift" else ""
    return typer.Option("--config", metavar="FILE", help=CONFIG_HELP.format(command=command, example=EXAMPLES.get(command, "seed = 3"), result=result),
                        rich_help_panel=panel, show_default=False)  # fmt: skip


def print_config_option(panel: str | None = None) -> Any:
    return typer.Option("--print-config", help=PRINT_CONFIG_HELP, rich_help_panel=panel)


def option_key(param: Any) -> str | None:
    """The option's key (`--min-confidence` -> `min_confidence`); None for an argument."""
    if getattr(param, "param_type_name", None) != "option":
        return None
    long = next((o for o in param.opts if o.startswith("--")), None)
    return long[2:].replace("-", "_") if long else None


def config_argument(args: list[str]) -> str | None:
    """The value of --config on a command line, the last one given as click reads it (None: none
    given, or --help asked)."""
    found = None
    for i, word in enumerate(args):
        if word == "--":
            break
        if word in ("--help", "-h"):
            return None
        if word == "--config" and i + 1 < len(args):  # without a value, click says so
            found = args[i + 1]
        elif word.startswith("--config="):
            found = word.split("=", 1)[1]
    return found


def model_of(command: str) -> type[Options]:
    module, name = MODELS[command]
    return getattr(importlib.import_module(f"zedo_cli.settings.{module}"), name)


def load_config(ctx: Any, command: Any, path: str) -> None:
    """Read `path` for `command` before its command line is parsed: its values become click's
    default_map (a flag given wins); an error is one line and exit code 2."""
    name = ctx.info_name or command.name or ""
    commands = ctx.parent.command.list_commands(ctx.parent) if ctx.parent is not None else []  # type: ignore[attr-defined]
    try:
        config = read_config(path, model_of(name), commands)
    except ZedoError as exc:
        sys.stderr.write(f"zedo: error: {one_line(str(exc))}\n")
        raise typer.Exit(exc.exit_code) from None
    names = {option_key(p): p.name for p in command.params if option_key(p) is not None}
    ctx.default_map = {**(ctx.default_map or {}), **{names[k]: v for k, v in config.values.items() if k in names}}
    ctx.meta[META] = config


@dataclass(frozen=True)
class Resolved:
    """A command's settings, where they came from and the config file read (if any)."""

    options: Any
    explicit: frozenset[str]  # the option keys given on the command line
    config: ConfigFile | None

    def expected_prior(self) -> str | None:
        """A result used as --config: the sha256 of the prior it was lifted with, unless --prior was given."""
        if self.config is None or "prior" in self.explicit:
            return None
        return self.config.prior_sha256


def resolve_options(model: type[Options]) -> Resolved:
    """The running command's settings: its options' values (defaults < --config < flags)
    validated as `model`. With --print-config they are printed as TOML and the command exits."""
    ctx = get_current_context()
    values: dict[str, Any] = {}
    explicit = set()
    keys = model.keys()
    for param in ctx.command.params:
        key = option_key(param)
        if key is None or key not in keys or param.name is None:
            continue
        values[key] = ctx.params[param.name]
        if ctx.get_parameter_source(param.name) not in (ParameterSource.DEFAULT, ParameterSource.DEFAULT_MAP):
            explicit.add(key)
    config: ConfigFile | None = ctx.meta.get(META)
    if config is not None:
        for key, why in config.needs.items():
            if key not in explicit:
                raise ConfigError(why)
    options = model.validated(values)
    if ctx.params.get("print_config"):
        sys.stdout.write(config_toml(options, config.path if config is not None else None))
        raise typer.Exit(0)
    if config is not None and not getattr(options, "quiet", False):
        for note in config.notes:
            sys.stderr.write(f"zedo: note: {one_line(note)}\n")
    return Resolved(options, frozenset(explicit), config)


def check_prior(resolved: Resolved, prior: Any) -> None:
    """A result used as --config: the prior that loaded is the one it was lifted with."""
    wanted = resolved.expected_prior()
    if wanted is not None and prior.sha256 != wanted:
        path = resolved.config.path if resolved.config is not None else "--config"
        raise ConfigError(f"{path}: lifted with a prior of sha256 {wanted[:12]}..., but {prior.label} is "
                          f"{prior.sha256[:12]}...: give that prior with --prior (or --prior X to lift with another)")  # fmt: skip
