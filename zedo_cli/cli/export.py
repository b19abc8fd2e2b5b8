"""`zedo export`: a zedo result written again in another format (TRC, C3D, CSV, JSON Lines, ...),
by the writers of `zedo lift` (formats.export), without lifting again."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Optional

import typer

from ..errors import ConfigError, plural
from ..formats.export import export_result
from ..formats.writers.markers import MARKER_AXES
from ..formats.writers.outputs import FRAMES, OUTPUT_FORMATS, UNITS, output_format
from ..lifting.people import PERSON_MODES
from .checks import MAX_FPS, check_choice, check_range
from .common import err_console, error_boundary, output_option
from .lift_plan import STDIN, check_output_options, output_stem, plan_outputs


def _output(result: str, out: str | None, fmt: str | None) -> str:
    """-o, else `<stem>.zedo.<format>` beside the result (`clip.zedo.json` -> `clip.zedo.trc`)."""
    if out is not None:
        return out
    if fmt is None:
        raise ConfigError("give -o/--output OUT.trc|.c3d|.csv|.jsonl|.json|.npz, or --format")
    folder = Path(".") if result == STDIN else Path(result).parent
    return str(folder / f"{output_stem(result)}.zedo.{output_format('x', fmt)}")


@error_boundary
def export_command(
    result: Annotated[
        str,
        typer.Argument(
            help="A zedo result: .json, .jsonl, .csv (with its .meta.json), .npz; - reads stdin.", show_default=False
        ),
    ],
    out: Annotated[
        Optional[str],
        output_option("The file to write; its format from its extension (- : stdout, for json, jsonl, csv)."),
    ] = None,
    fmt: Annotated[
        Optional[str],
        typer.Option(
            "--format",
            "--output-format",
            help=f"{', '.join(OUTPUT_FORMATS)}. Default: from -o. Without -o: <stem>.zedo.<format> beside the result.",
        ),
    ] = None,
    units: Annotated[
        Optional[str], typer.Option(help=f"{', '.join(UNITS)} (TRC is always m, C3D mm). Default: the result's.")
    ] = None,
    frame: Annotated[
        Optional[str], typer.Option(help=f"{', '.join(FRAMES)}: as zedo lift --frame. Default: the result's.")
    ] = None,
    marker_axes: Annotated[
        str,
        typer.Option(help=f"Axes of TRC / C3D files: {', '.join(MARKER_AXES)} (overhead: a camera above an infant)."),
    ] = "level",
    person: Annotated[
        str,
        typer.Option(
            help=f"Whom to keep in a frame of several: {', '.join(PERSON_MODES)} (as zedo lift chooses, from the "
            "result's 2D)."
        ),
    ] = "all",
    fps: Annotated[
        Optional[float],
        typer.Option(help="Frame rate of a result lifted without --fps (TRC / C3D of frames without numbers)."),
    ] = None,
    overwrite: Annotated[bool, typer.Option(help="Replace outputs that exist.")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No summary on stderr.")] = False,
) -> None:
    """Write a zedo result in another format, with the writers of zedo lift.

    Any result zedo reads (JSON, JSON Lines, CSV with its sidecar, NPZ) becomes a TRC or C3D
    marker file for OpenSim / Pose2Sim, a CSV, JSON Lines, JSON or NPZ result, as zedo lift -o
    would have written it from the same lift (docs/exports.md). Nothing is lifted again. A
    marker file is written per person with --person all (<stem>_P1.trc, ...).

    Examples:

      zedo export clip.zedo.json -o clip.trc

      zedo export clip.zedo.json -o clip.c3d --marker-axes overhead

      zedo export clip.zedo.jsonl --format csv   # -> clip.zedo.csv beside it
    """
    if units is not None:
        check_choice("--units", units, UNITS)
    if frame is not None:
        check_choice("--frame", frame, FRAMES)
    check_choice("--marker-axes", marker_axes, tuple(MARKER_AXES))
    check_choice("--person", person, PERSON_MODES)
    check_range("--fps", fps, 0, MAX_FPS, low_open=True)
    output = _output(result, out, fmt)
    check_output_options(output, None, fmt)
    plan_outputs([result], output, None, fmt, overwrite)  # the lift's checks: exists, folder, the input itself
    done = export_result(result, output, fmt=fmt, units=units, frame=frame, marker_axes=marker_axes, person=person,
                         fps=fps, overwrite=overwrite)  # fmt: skip
    if not quiet and done.written:
        err_console.print(f"exported {plural(done.instances, 'instance')} ({done.lifted} lifted) from {result} "
                          f"as {done.format}; wrote {', '.join(str(p) for p in done.written)}",
                          markup=False, soft_wrap=True)  # fmt: skip
