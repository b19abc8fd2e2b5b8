"""`ExportOptions`: every option of `zedo export`, for the command line and `--config`."""

from __future__ import annotations

from typing import ClassVar, Literal, Optional

from pydantic import Field

from ..formats import OUTPUT_FORMATS
from ..formats.writers.markers import MARKER_AXES
from ..formats.writers.outputs import FRAMES, UNITS
from ..lifting.people import PERSON_MODES
from .limits import MAX_FPS
from .model import Options


class ExportOptions(Options):
    """The settings of `zedo export`, one field per long option (named as `zedo lift`'s where they mean the same)."""

    command: ClassVar[str] = "export"

    output: Optional[str] = Field(
        None, description="The file to write; its format from its extension (- : stdout, for json, jsonl, csv)."
    )
    output_format: Optional[Literal[OUTPUT_FORMATS]] = Field(  # type: ignore[valid-type]
        None,
        description=f"{', '.join(OUTPUT_FORMATS)}. Default: from -o. Without -o: <stem>.zedo.<format> beside the "
        "result.",
    )
    units: Optional[Literal[UNITS]] = Field(  # type: ignore[valid-type]
        None, description=f"{', '.join(UNITS)} (TRC is always m, C3D mm). Default: the result's."
    )
    frame: Optional[Literal[FRAMES]] = Field(  # type: ignore[valid-type]
        None, description=f"{', '.join(FRAMES)}: as zedo lift --frame. Default: the result's."
    )
    marker_axes: Literal[tuple(MARKER_AXES)] = Field(  # type: ignore[valid-type]
        "level",
        description=f"Axes of TRC / C3D files: {', '.join(MARKER_AXES)} (overhead: a camera above an infant).",
    )
    person: Literal[PERSON_MODES] = Field(  # type: ignore[valid-type]
        "all",
        description=f"Whom to keep in a frame of several: {', '.join(PERSON_MODES)} (as zedo lift chooses, from the "
        "result's 2D).",
    )
    fps: Optional[float] = Field(
        None, gt=0, le=MAX_FPS, description="Frame rate of a result lifted without --fps (TRC / C3D of frames without "
        "numbers).",
    )  # fmt: skip
    overwrite: bool = Field(False, description="Replace outputs that exist.")
    quiet: bool = Field(False, description="No summary on stderr.")
