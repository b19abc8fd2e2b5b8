"""`zedo export`: a zedo result written again in another format (TRC, C3D, CSV, JSON Lines, ...),
by the writers of `zedo lift` (formats.export), without lifting again."""

from __future__ import annotations

from functools import partial
from pathlib import Path
from typing import Annotated, Optional

import typer

from ..errors import ConfigError, plural
from ..formats.export import export_result
from ..formats.writers.outputs import output_format as format_of
from ..settings.export import ExportOptions
from .common import err_console, error_boundary, output_option
from .config import config_option, model_option, print_config_option, resolve_options
from .lift_plan import STDIN, check_output_options, output_stem, plan_outputs


def _output(result: str, out: str | None, fmt: str | None) -> str:
    """-o, else `<stem>.zedo.<format>` beside the result (`clip.zedo.json` -> `clip.zedo.trc`)."""
    if out is not None:
        return out
    if fmt is None:
        raise ConfigError("give -o/--output OUT.trc|.c3d|.csv|.jsonl|.json|.npz, or --format")
    folder = Path(".") if result == STDIN else Path(result).parent
    return str(folder / f"{output_stem(result)}.zedo.{format_of('x', fmt)}")


_opt = partial(model_option, ExportOptions)  # the option `key` of ExportOptions, with the model's help text


@error_boundary
def export_command(
    result: Annotated[
        str,
        typer.Argument(
            help="A zedo result: .json, .jsonl, .csv (with its .meta.json), .npz; - reads stdin.", show_default=False
        ),
    ],
    out: Annotated[Optional[str], output_option(ExportOptions.help("output"))] = None,
    output_format: Annotated[Optional[str], _opt("output_format", "--output-format", "--format")] = None,
    units: Annotated[Optional[str], _opt("units")] = None,
    frame: Annotated[Optional[str], _opt("frame")] = None,
    marker_axes: Annotated[str, _opt("marker_axes")] = "level",
    person: Annotated[str, _opt("person")] = "all",
    fps: Annotated[Optional[float], _opt("fps")] = None,
    overwrite: Annotated[bool, _opt("overwrite")] = False,
    quiet: Annotated[bool, _opt("quiet", "--quiet", "-q")] = False,
    config: Annotated[Optional[Path], config_option("export")] = None,
    print_config: Annotated[bool, print_config_option()] = False,
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
    o: ExportOptions = resolve_options(ExportOptions).options
    output = _output(result, o.output, o.output_format)
    check_output_options(output, None, o.output_format)
    plan_outputs([result], output, None, o.output_format, o.overwrite)  # the lift's checks: exists, folder, the input
    done = export_result(result, output, fmt=o.output_format, units=o.units, frame=o.frame, marker_axes=o.marker_axes,
                         person=o.person, fps=o.fps, overwrite=o.overwrite)  # fmt: skip
    if not o.quiet and done.written:
        err_console.print(f"exported {plural(done.instances, 'instance')} ({done.lifted} lifted) from {result} "
                          f"as {done.format}; wrote {', '.join(str(p) for p in done.written)}",
                          markup=False, soft_wrap=True)  # fmt: skip
