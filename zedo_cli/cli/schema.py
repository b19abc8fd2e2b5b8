"""`zedo schema`: print the published JSON Schema of a zedo file (today: the result file)."""

from __future__ import annotations

import json
import sys
from typing import Annotated, Optional

import typer

from ..errors import ConfigError
from ..files import write_text_atomic
from .common import error_boundary

SCHEMAS = ("result",)


# fmt: off
@error_boundary
def schema_command(
    name: Annotated[str, typer.Argument(help=f"Which file's schema: {', '.join(SCHEMAS)} (the zedo.pose3d/1 result of zedo lift, JSON and JSON Lines).")],
    out: Annotated[Optional[str], typer.Option("--out", "-o", help="Write the schema to this file instead of stdout.")] = None,
    overwrite: Annotated[bool, typer.Option(help="Replace an existing --out file.")] = False,
) -> None:
    """Print the JSON Schema (draft 2020-12) of a zedo file, generated from the models zedo reads it with.

    The result schema describes the JSON document of zedo lift; each JSON Lines line is its
    header (with "type": "header"), one of its frames ("type": "frame") or its summary
    ("type": "summary"). Per-joint lists have one entry per skeleton joint. See docs/exports.md.

      zedo schema result > zedo.pose3d.schema.json
    """
    # fmt: on
    if name not in SCHEMAS:
        raise ConfigError(f"unknown schema {name!r}; choose one of: {', '.join(SCHEMAS)}")
    from ..formats.result_schema import result_json_schema

    text = json.dumps(result_json_schema(), indent=2) + "\n"
    if out is None or out == "-":
        sys.stdout.write(text)
    else:
        write_text_atomic(out, text, overwrite=overwrite)
