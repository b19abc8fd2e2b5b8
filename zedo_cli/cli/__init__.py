"""The `zedo` command line: thin adapters over the library. The only place typer and rich are used."""

from __future__ import annotations

import typer

from .fit import fit_prior_command

app = typer.Typer(
    name="zedo",
    help=(
        "Lift 2D infant body keypoints to 3D with a diffusion pose prior (ZeDO-i).\n\n"
        "Exit codes: 0 success, 1 runtime failure, 2 usage error (bad option or value), "
        "3 unreadable or invalid input file, 130 interrupted."
    ),
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


@app.callback()
def _root() -> None:
    """Lift 2D infant body keypoints to 3D with a diffusion pose prior (ZeDO-i)."""


app.command("fit-prior", no_args_is_help=True)(fit_prior_command)


def main() -> None:
    app()
