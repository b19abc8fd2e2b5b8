"""The `zedo` command line: thin adapters over the library. The only place typer and rich are used."""

from __future__ import annotations

from typing import Annotated

import typer

from ..version import __version__
from .help import ZedoGroup
from .lazy_commands import LazyCommand

# In this order in `zedo --help`, in two panels: the commands of an analyst's day (2D keypoints to 3D
# poses, measures, footage, cameras, files) first, then those of training priors and benchmarking
# them. Each shows a short usage when run without arguments (cli/help.py).
# A command's module is imported only when it runs or shows its own help, so that `zedo --help` and
# `zedo lift` start fast (docs/lifting.md, "Start-up and large batches"); each summary is the first
# line of the function's docstring (tests/cli/test_startup.py checks it). One command a line.
ANALYSIS_PANEL = "Commands"
RESEARCH_PANEL = "Research: priors, augmentation, benchmarks"
# fmt: off
PANELS: dict[str, dict[str, LazyCommand]] = {
    ANALYSIS_PANEL: {
        "lift": LazyCommand("lift", "lift_command", "Lift 2D keypoints to 3D poses, in the camera frame (x right, y down, z forward)."),
        "analyze": LazyCommand("analyze", "analyze_command", "Clinical measures of lifted poses: symmetry, joint angles, movement."),
        "norms": LazyCommand("norms", "norms_command", "Build a reference of typical infants for zedo analyze --norms."),
        "render": LazyCommand("render", "render_command", "Draw the lifted skeletons over the footage, to see how well the 3D poses fit."),
        "export": LazyCommand("export", "export_command", "Write a zedo result in another format, with the writers of zedo lift."),
        "calibrate": LazyCommand("calibrate", "calibrate_command", "Calibrate a camera from views of a printed checkerboard."),
        "schema": LazyCommand("schema", "schema_command", "Print the JSON Schema (draft 2020-12) of a zedo file, generated from the models zedo reads it with."),
    },
    RESEARCH_PANEL: {
        "fit-prior": LazyCommand("fit", "fit_prior_command", "Train a score-matching diffusion prior over 3D poses and write it as a weights file."),
        "adapt": LazyCommand("adapt", "adapt_command", "Adapt a pose prior to a small infant 3D data set; write a prior `zedo lift` loads."),
        "fit-augmenter": LazyCommand("augment", "fit_augmenter_command", "Train the domain-conditioned network of `zedo augment` on adult and infant 3D poses."),
        "augment": LazyCommand("augment", "augment_command", "Convert adult 3D poses into infant-like ones with a domain-conditioned diffusion model."),
        "evaluate": LazyCommand("evaluate", "evaluate_command", "Score lifted poses against 3D ground truth: MPJPE and PA-MPJPE in mm."),
        "benchmark": LazyCommand("evaluate", "benchmark_command", "Run the paper's SyRIP Test100 benchmark for one or more presets, side by side."),
        "benchmark-minirgbd": LazyCommand("minirgbd", "benchmark_minirgbd_command", "Run the MINI-RGBD benchmark: lift the test frames from their 2D and score MPJPE / PA-MPJPE."),
        "benchmark-symmetry": LazyCommand("analyze", "benchmark_symmetry_command", "How accurate zedo analyze's measures are, on SyRIP Test100."),
    },
}
# fmt: on
COMMANDS = {name: command for commands in PANELS.values() for name, command in commands.items()}


class _ZedoApp(ZedoGroup):
    """The `zedo` group over the panels above."""

    panels = PANELS


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
    cls=_ZedoApp,
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


def main() -> None:
    app()
