"""`AnalyzeOptions`: every option of `zedo analyze`, for the command line, `--config` and `zedo_cli.analyze`."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, ClassVar, Optional

from pydantic import Field, ValidationInfo, field_validator

from ..analysis.analyse import DEFAULT_MAX_VELOCITY_DEG_S, AnalysisSettings
from ..analysis.norms.norms import MAX_AGE_WEEKS, check_age_weeks
from ..analysis.pose.symmetry import DEFAULT_THRESHOLD_DEG
from ..analysis.uncertainty.calibration import DEFAULT_CALL_LEVEL, DEFAULT_LEVEL, LEVELS
from ..errors import ConfigError
from .limits import MAX_FPS, MAX_SYMMETRY_THRESHOLD_DEG
from .model import Options, option_name

PathOption = Annotated[Optional[Path], Field(strict=False)]
_LEVELS = f"one of {', '.join(map(str, LEVELS))}"


class AnalyzeOptions(Options):
    """The settings of `zedo analyze` (and of `zedo_cli.analyze`), one field per long option."""

    command: ClassVar[str] = "analyze"

    output: Optional[str] = Field(
        None,
        description="The tidy CSV (.csv) or the JSON (.json) of one input; - : the CSV on stdout. Default: "
        "<stem>.analysis.csv and .json beside the input.",
    )
    output_dir: PathOption = Field(
        None, description="Write <stem>.analysis.csv and .json of every input into this folder (made if missing)."
    )
    as_json: bool = Field(
        False, alias="json", description="Print the JSON (rows, settings, summary) on stdout instead."
    )
    report: PathOption = Field(
        None,
        description="Also write a self-contained HTML report per input, <stem>.report.html, into this folder.",
    )
    symmetry_threshold: float = Field(
        DEFAULT_THRESHOLD_DEG,
        ge=0,
        le=MAX_SYMMETRY_THRESHOLD_DEG,
        description="Symmetric when the symmetry angle is at most this many degrees (the paper's 3D value).",
    )
    fps: Optional[float] = Field(
        None,
        gt=0,
        le=MAX_FPS,
        description="Frame rate: treat the result as a video (movement features); needed with a --video whose "
        "file stores none (a raw MJPEG or H.264 stream). Default: the fps zedo lift recorded, else the frames are "
        "separate images.",
    )
    level: float = Field(
        DEFAULT_LEVEL,
        description=f"Coverage of the intervals: {_LEVELS}.",
        json_schema_extra={"expected": _LEVELS},
    )
    call_level: float = Field(
        DEFAULT_CALL_LEVEL,
        description="The symmetry calls use the interval of this level (0.8: each end misses the truth at "
        "most 10 % of the time, so a call is right about 9 times in 10; 0.9: fewer calls).",
        json_schema_extra={"expected": _LEVELS},
    )
    max_angular_velocity: float = Field(
        DEFAULT_MAX_VELOCITY_DEG_S,
        gt=0,
        description="Joint angles changing faster than this (deg/s) are flagged too_fast and left out of the "
        "movement features.",
    )
    norms: PathOption = Field(
        None,
        description="A reference of typical infants (from zedo norms, at least 20 clips): each clip feature's z, the "
        "published comparison (surprise_published_z, _p) and the calibrated p of the extended features and of the "
        "left-right asymmetry (surprise_extended_p, surprise_asymmetry_p: p < 0.05 for at most 1 typical clip in "
        "20).",
    )
    age_weeks: Optional[float] = Field(
        None,
        description="The infant's age in weeks, for a reference split by age (--norms).",
        json_schema_extra={"expected": f"a number of weeks, 0 to {MAX_AGE_WEEKS:g}"},
    )
    video: PathOption = Field(
        None,
        description="The clip's video (with --report): thumbnails of the frames to review, the skeleton drawn "
        "over them. A video that does not fit the result (frames, size) is refused.",
    )
    images: PathOption = Field(
        None, description="The clip's frames as a folder of images (with --report), instead of --video."
    )
    overwrite: bool = Field(False, description="Replace output files that exist.")
    quiet: bool = Field(False, description="No summary on stderr.")

    @field_validator("level", "call_level")
    @classmethod
    def _a_level(cls, value: float, info: ValidationInfo) -> float:
        if value not in LEVELS:
            raise ValueError(f"{option_name(info.field_name or 'level')} must be {_LEVELS}, got {value:g}")
        return value

    @field_validator("age_weeks")
    @classmethod
    def _an_age(cls, value: float | None) -> float | None:
        try:
            check_age_weeks(value)  # the one bound of zedo norms and zedo analyze
        except ConfigError as exc:
            raise ValueError(str(exc)) from None
        return value

    def check(self) -> None:
        if self.age_weeks is not None and self.norms is None:
            raise ConfigError("--age-weeks picks the age bracket of a reference: give it with --norms")

    def analysis_settings(self) -> AnalysisSettings:
        return AnalysisSettings(self.symmetry_threshold, self.fps, self.level, self.call_level,
                                self.max_angular_velocity)  # fmt: skip
