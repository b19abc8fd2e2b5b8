"""`zedo schema`: print the published JSON Schema of a zedo file (the result, the analysis)."""

from __future__ import annotations

import json
import sys
from typing import Annotated, Optional

import typer

from ..errors import ConfigError
from ..files import write_text_atomic
from .common import err_console, error_boundary, output_option

SCHEMAS = ("result", "analysis")


# fmt: off
@error_boundary
def schema_command(
    name: Annotated[str, typer.Argument(help=f"Which file's schema: {', '.join(SCHEMAS)} (the zedo.pose3d/1 result of zedo lift, JSON and JSON Lines; the zedo.analysis/2 JSON of zedo analyze).")],
    out: Annotated[Optional[str], output_option("Write the schema to this file instead of stdout.")] = None,
    overwrite: Annotated[bool, typer.Option(help="Replace the output if it exists.")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No note on stderr.")] = False,
) -> None:
    """Print the JSON Schema (draft 2020-12) of a zedo file, generated from the models zedo reads it with.

    The result schema describes the JSON document of zedo lift; each JSON Lines line is its
    header (with "type": "header"), one of its frames ("type": "frame") or its summary
    ("type": "summary"). Per-joint lists have one entry per skeleton joint. See docs/exports.md.
    The analysis schema describes the JSON of zedo analyze: its rows have the CSV's columns.

    Examples:

      zedo schema result -o zedo.pose3d.schema.json
      zedo schema analysis -o zedo.analysis.schema.json
    """
    # fmt: on
    if name not in SCHEMAS:
        raise ConfigError(f"unknown schema {name!r}; choose one of: {', '.join(SCHEMAS)}")
    if name == "result":
        from ..formats.result_schema import result_json_schema as json_schema
    else:
        from ..analysis.schema import analysis_json_schema as json_schema

    text = json.dumps(json_schema(), indent=2) + "\n"
    if out is None or out == "-":
        sys.stdout.write(text)
    else:
        write_text_atomic(out, text, overwrite=overwrite)
        if not quiet:
            err_console.print(f"wrote {out}", markup=False, soft_wrap=True)
