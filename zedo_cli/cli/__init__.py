"""The `zedo` command line: thin adapters over the library. The only place typer and rich are used."""

from __future__ import annotations

from collections.abc import Callable
from typing import Annotated

import typer

from ..version import __version__
from .adapt import adapt_command
from .analyze import analyze_command, benchmark_symmetry_command
from .augment import augment_command, fit_augmenter_command
from .calibrate import calibrate_command
from .evaluate import benchmark_command, evaluate_command
from .export import export_command
from .fit import fit_prior_command
from .help import ZedoCommand, ZedoGroup
from .lift import lift_command
from .minirgbd import benchmark_minirgbd_command
from .norms import norms_command
from .render import render_command
from .schema import schema_command

app = typer.Typer(
    name="zedo",
    help=(
        "Lift 2D infant body keypoints to 3D with a diffusion pose prior (ZeDO-i).\n\n"
        "Exit codes: 0 success, 1 runtime failure, 2 usage error (bad option or value), "
        "3 unreadable or invalid input file, 4 some inputs of a batch failed (the others were written), "
        "5 an output could not be written (full disk, read-only folder), "
        "6 zedo calibrate refused an untrustworthy camera, "
        "130 interrupted, 141 stdout closed by its reader."
    ),
    cls=ZedoGroup,
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


def _print_version(value: bool) -> None:
    if value:
        typer.echo(f"zedo {__version__}")
        raise typer.Exit()


@app.callback()
def _root(
    version: Annotated[
        bool,
        typer.Option("--version", is_eager=True, callback=_print_version, help="Print zedo's version and exit."),
    ] = False,
) -> None:
    """Lift 2D infant body keypoints to 3D with a diffusion pose prior (ZeDO-i)."""


# In this order in `zedo --help`, in two panels: the commands of an analyst's day (2D keypoints to 3D
# poses, measures, footage, cameras, files) first, then those of training priors and benchmarking
# them. Each shows a short usage when run without arguments (cli/help.py).
ANALYSIS_PANEL = "Commands"
RESEARCH_PANEL = "Research: priors, augmentation, benchmarks"
PANELS: dict[str, dict[str, Callable[..., None]]] = {
    ANALYSIS_PANEL: {
        "lift": lift_command,
        "analyze": analyze_command,
        "norms": norms_command,
        "render": render_command,
        "export": export_command,
        "calibrate": calibrate_command,
        "schema": schema_command,
    },
    RESEARCH_PANEL: {
        "fit-prior": fit_prior_command,
        "adapt": adapt_command,
        "fit-augmenter": fit_augmenter_command,
        "augment": augment_command,
        "evaluate": evaluate_command,
        "benchmark": benchmark_command,
        "benchmark-minirgbd": benchmark_minirgbd_command,
        "benchmark-symmetry": benchmark_symmetry_command,
    },
}
COMMANDS = {name: command for commands in PANELS.values() for name, command in commands.items()}
for _panel, _commands in PANELS.items():
    for _name, _command in _commands.items():
        app.command(_name, no_args_is_help=True, cls=ZedoCommand, rich_help_panel=_panel)(_command)


def main() -> None:
    app()
