"""`NormsOptions`: every option of `zedo norms`, for the command line and `--config`."""

from __future__ import annotations

from pathlib import Path
from typing import ClassVar, Optional

from pydantic import Field, field_validator

from ..analysis.norms.norms import AGE_THRESHOLD_WEEKS, MAX_AGE_WEEKS, check_age_weeks
from ..errors import ConfigError
from .limits import MAX_FPS
from .model import Options


class NormsOptions(Options):
    """The settings of `zedo norms`, one field per long option."""

    command: ClassVar[str] = "norms"

    output: str = Field("norms.json", description="The reference to write (.json).")
    age_weeks: Optional[list[float]] = Field(
        None,
        description=f"Age in weeks: once (every clip) or once per clip, in order. With ages, the reference is "
        f"split at {AGE_THRESHOLD_WEEKS:g} weeks as published; without, one bracket.",
        json_schema_extra={"expected": f"numbers of weeks, 0 to {MAX_AGE_WEEKS:g}"},
    )
    fps: Optional[float] = Field(None, gt=0, le=MAX_FPS, description="Frame rate, where zedo lift recorded none.")
    overwrite: bool = Field(False, description="Replace the output if it exists.")
    quiet: bool = Field(False, description="No progress bar or summary.")

    @field_validator("age_weeks", mode="before")
    @classmethod
    def _a_list(cls, value: object) -> object:
        """The command line gives the repeated option as a tuple (none given: an empty one)."""
        return (list(value) or None) if isinstance(value, tuple) else value

    @field_validator("age_weeks")
    @classmethod
    def _ages(cls, value: list[float] | None) -> list[float] | None:
        try:
            for age in value or ():
                check_age_weeks(age)  # the one bound of zedo norms and zedo analyze
        except ConfigError as exc:
            raise ValueError(str(exc)) from None
        return value

    def check(self) -> None:
        if Path(self.output).suffix.lower() != ".json":
            raise ConfigError(f"{self.output}: -o/--output writes the reference as .json")

    def ages_per_input(self, count: int) -> list[float | None]:
        """--age-weeks for `count` inputs: none, one age for every input, or one per input in order."""
        ages = self.age_weeks
        if not ages:
            return [None] * count
        if len(ages) == 1:
            return [ages[0]] * count
        if len(ages) != count:
            raise ConfigError(f"--age-weeks: give one age for every clip or one per clip ({count}), got {len(ages)}")
        return list(ages)
