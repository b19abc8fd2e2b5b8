"""The published schema of the analysis file (`zedo.analysis/2`, the JSON of `zedo analyze`): pydantic models of
the document and its rows, and the JSON Schema generated from them (`zedo schema analysis`). The CSV has the rows'
columns (`table.COLUMNS`) in the same order. Unknown values are null; numbers are finite."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field

from .table import INTERVAL_METHODS

SCHEMA = "zedo.analysis/2"

IntervalMethod = Literal[("", *INTERVAL_METHODS)]  # "": a row without an interval
Call = Literal["", "symmetric", "asymmetric", "uncertain", "left", "right", "midline"]


class _Closed(BaseModel):
    model_config = ConfigDict(extra="forbid")


class AnalysisRow(_Closed):
    """One row of the tidy table: a measure of a frame and person, or of a person's clip (frame columns null)."""

    frame_index: int | None = Field(description="the result's frame number; null for a clip's row")
    image_id: int | str | None
    file_name: str | None
    person: int = Field(ge=0, description="the person's place in its frame (a track in a clip)")
    measure: str = Field(description="the measure's name (docs/measures.md)")
    value: float | None = Field(description="the estimate (calibrated where a calibration holds); null: unknown")
    unit: str
    low: float | None = Field(description="the interval's low end at `level`; null: no interval")
    high: float | None = Field(description="the interval's high end at `level`")
    level: float | None = Field(description="the coverage `low` and `high` are calibrated to (--level)")
    call: Call = Field(description="symmetric / asymmetric / uncertain, or the head turn's side; '' where none")
    interval: IntervalMethod = Field(description="how the interval was obtained: " + "; ".join(
        f"{code}: {meaning}" for code, meaning in INTERVAL_METHODS.items()))  # fmt: skip
    interval_note: str = Field(description="more on the interval; for `none`, why there is none")
    raw_value: float | None = Field(description="the measure of the reported pose, before calibration")
    flag: str = Field(description="too_fast, eye_line_reversed, or ''")
    call_low: float | None = Field(description="the interval at --call-level that decides `call`")
    call_high: float | None


class AnalysisInput(_Closed):
    path: str
    format: str
    skeleton: str
    coordinate_frame: str
    units_in_file: str
    persons: int = Field(ge=0)
    persons_analysed: int = Field(ge=0)
    frames: int = Field(ge=0)


class AnalysisSettingsBlock(_Closed):
    symmetry_threshold_deg: float
    symmetry_bands_deg: list[float]
    fps: float | None
    fps_source: Literal["option", "result", "none"]
    interval_level: float
    max_angular_velocity_deg_s: float


class Backing(_Closed):
    """A measure calibration that backs intervals of the analysis."""

    id: str
    scope: Literal["frames", "clips"]
    temporal_mode: str | None
    cameras: list[str]
    camera_range: str | None
    data: str | None


class Uncertainty(_Closed):
    available: bool
    note: str
    level: float
    calibrations: list[Backing]
    method: str
    interval_methods: dict[str, str]


class AnalysisDocument(_Closed):
    """The JSON document `zedo analyze` writes (`<stem>.analysis.json`)."""

    model_config = ConfigDict(
        extra="forbid", title=f"zedo analysis ({SCHEMA})",
        json_schema_extra={"$schema": "https://json-schema.org/draft/2020-12/schema"},
    )  # fmt: skip
    schema_: Literal["zedo.analysis/2"] = Field(alias="schema")
    zedo_version: str
    created: str = Field(description="ISO 8601 time of writing")
    input: AnalysisInput
    settings: AnalysisSettingsBlock
    uncertainty: Uncertainty
    notes: list[str]
    columns: list[str] = Field(description="the rows' keys, and the CSV's columns, in order")
    measures: dict[str, str] = Field(description="measure families and what they mean")
    summary: dict[str, dict[str, float | int]]
    rows: list[AnalysisRow]


def analysis_json_schema() -> dict[str, Any]:
    """The JSON Schema (draft 2020-12) of the analysis document."""
    return AnalysisDocument.model_json_schema(by_alias=True)
