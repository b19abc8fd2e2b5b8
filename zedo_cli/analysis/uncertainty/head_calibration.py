"""The calibration of the head's clip intervals (docs/clinical.md, "Head"): per measure, a
measurement error and per level a factor that widen the block bootstrap interval's arms so that
that share of the intervals hold the truth.

The block bootstrap (`block_bootstrap`) resamples a clip's frames; it knows neither that each
frame's call or tilt is itself wrong sometimes (a frame near the 20-degree boundary called to the
wrong side, a one-sided view, pixel noise on the eye line), which moves the long-run share of
calls away from the true share by an amount no longer clip makes smaller, nor that a clip of a
few long holds says little about its own variance; alone it under-covers. So, per measure:

1. the measurement error: the root mean square, over calibration processes, of the difference
   between the measure's long-run value as measured (2 hours, frames as the clips' frames) and
   its truth; it is added in quadrature to each arm of the bootstrap interval;
2. split conformal on the arms so made: on calibration clips with a known truth, the score of a
   clip is |truth - estimate| over the arm on the truth's side; the factor is the scores'
   conformal quantile (the ceil((n + 1) level)-th smallest of n), and a new clip's arms are
   multiplied by it. One bootstrap interval (at the bootstrap's own level, 90 %) serves every
   level: only the quantile changes.

The truths are those of `benchmarks/calibrate/head_measures.py`: a share is the process's long-run share of
frames by the head's true yaw, the median tilt the long-run median of the tilt's definition on the
noiseless points; the clips measured for the held-out coverage are other infants' poses and seeds.

A calibration holds for the settings it was fitted with (`HeadSettings` except `min_confidence`,
and the bootstrap's except its seed); other settings get no interval. The bundled file is
`zedo_cli/weights/head.json` (`python benchmarks/calibrate/head_measures.py --write`).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np
from pydantic import Field, field_validator

from ...stats import conformal_quantile
from ...versioned_json import FileModel, ShippedFile
from .block_bootstrap import BootstrapSettings, ClipInterval

FORMAT = "zedo.head_intervals"
FORMAT_VERSION = 1
MEASURES = ("head_turn_fraction_left", "head_turn_fraction_right", "head_turn_fraction_midline",
            "head_tilt_median_deg")  # fmt: skip
BOUNDS = {"head_turn_fraction_left": (0.0, 1.0), "head_turn_fraction_right": (0.0, 1.0),
          "head_turn_fraction_midline": (0.0, 1.0), "head_tilt_median_deg": (-90.0, 90.0)}  # fmt: skip


def head_settings_key(midline_deg: float, model: Any, bootstrap: BootstrapSettings) -> dict[str, Any]:
    """What a calibration is matched on: the call's midline, the head model and the bootstrap's
    settings (not its seed)."""
    boot = {k: v for k, v in asdict(bootstrap).items() if k != "seed"}
    return {"midline_deg": float(midline_deg), "model": asdict(model), "bootstrap": boot}


@dataclass(frozen=True)
class MeasureFactor:
    """One measure's factor and what backs it."""

    factor: float  # the arms' multiplier (conformal quantile of the scores)
    calibration_clips: int  # scores it was fitted on
    held_out_coverage: float  # of the widened intervals, on clips not used to fit it
    held_out_clips: int


@dataclass(frozen=True)
class HeadMeasureCalibration:
    """One measure's calibration: the frames' own error on its long-run value, and a factor per level."""

    error: float  # the measurement error (the measure's unit), added to each arm in quadrature
    levels: dict[float, MeasureFactor]


@dataclass(frozen=True)
class HeadCalibration:
    """The calibration of the head's clip measures for one set of settings (`head_settings_key`):
    per measure its measurement error and its factor per interval level (the bootstrap's interval
    is the same for every level; the level picks the factor)."""

    settings: dict[str, Any]
    measures: dict[str, HeadMeasureCalibration]  # every one of MEASURES
    provenance: str  # how it was made (the command)


# The file's entries (pydantic): what `read_head_calibrations` validates and `write_head_calibrations` writes; `of`
# makes one of the dataclass the code computes with (the written precision: 4 decimals, the error 5), `value` the
# dataclass.


class MeasureFactorEntry(FileModel):
    factor: float = Field(gt=0, allow_inf_nan=False)
    calibration_clips: int
    held_out_coverage: float = Field(ge=0.0, le=1.0, allow_inf_nan=False)
    held_out_clips: int

    @classmethod
    def of(cls, f: MeasureFactor) -> MeasureFactorEntry:
        return cls(factor=round(f.factor, 4), calibration_clips=f.calibration_clips,
                   held_out_coverage=round(f.held_out_coverage, 4), held_out_clips=f.held_out_clips)  # fmt: skip

    def value(self) -> MeasureFactor:
        return MeasureFactor(self.factor, self.calibration_clips, self.held_out_coverage, self.held_out_clips)


class HeadMeasureEntry(FileModel):
    error: float = Field(ge=0.0, allow_inf_nan=False)
    levels: dict[str, MeasureFactorEntry] = Field(min_length=1)  # level ("0.9", in (0, 1)) -> its factor

    @field_validator("levels")
    @classmethod
    def _levels_in_range(cls, levels: dict[str, MeasureFactorEntry]) -> dict[str, MeasureFactorEntry]:
        for key in levels:
            try:
                level = float(key)
            except ValueError:
                level = math.nan
            if not 0.0 < level < 1.0:
                raise ValueError(f"level {key} must be in (0, 1)")
        return levels

    @classmethod
    def of(cls, c: HeadMeasureCalibration) -> HeadMeasureEntry:
        return cls(error=round(c.error, 5), levels={str(k): MeasureFactorEntry.of(f) for k, f in c.levels.items()})

    def value(self) -> HeadMeasureCalibration:
        return HeadMeasureCalibration(self.error, {float(k): f.value() for k, f in self.levels.items()})


class HeadCalibrationEntry(FileModel):
    settings: dict[str, Any]
    provenance: str
    measures: dict[str, HeadMeasureEntry]  # every one of MEASURES

    @field_validator("measures")
    @classmethod
    def _every_measure(cls, measures: dict[str, HeadMeasureEntry]) -> dict[str, HeadMeasureEntry]:
        missing = [m for m in MEASURES if m not in measures]
        if missing:
            raise ValueError(f"missing {', '.join(missing)}")
        return measures

    @classmethod
    def of(cls, c: HeadCalibration) -> HeadCalibrationEntry:
        return cls(settings=c.settings, provenance=c.provenance,
                   measures={m: HeadMeasureEntry.of(v) for m, v in c.measures.items()})  # fmt: skip

    def value(self) -> HeadCalibration:
        return HeadCalibration(dict(self.settings), {m: v.value() for m, v in self.measures.items()}, self.provenance)


_FILE = ShippedFile("head.json", FORMAT, FORMAT_VERSION, "calibrations", "head interval calibration",
                    HeadCalibrationEntry)  # fmt: skip


def read_head_calibrations(path: str | Path) -> list[HeadCalibration]:
    """The calibrations of a head-interval calibration file (format `zedo.head_intervals`, version 1)."""
    return _FILE.read(path)


def write_head_calibrations(path: str | Path, calibrations: Sequence[HeadCalibration]) -> None:
    _FILE.write(path, calibrations)


def bundled_path() -> Path:
    return _FILE.bundled_path()


@functools.cache
def bundled_head_calibrations() -> tuple[HeadCalibration, ...]:
    return _FILE.read_bundled()


def find_head_calibration(calibrations: Sequence[HeadCalibration], key: dict[str, Any]) -> HeadCalibration | None:
    """The calibration fitted with the settings `key` (`head_settings_key`), else None."""
    return next((c for c in calibrations if c.settings == key), None)


def scores(estimate: np.ndarray, low: np.ndarray, high: np.ndarray, truth: np.ndarray, error: float) -> np.ndarray:
    """Per clip `(n,)`: |truth - estimate| over the arm on the truth's side with the measurement
    error added in quadrature (inf where both are 0 and the truth elsewhere, 0 where the truth is
    the estimate)."""
    arm = np.hypot(np.where(truth >= estimate, high - estimate, estimate - low), error)
    gap = np.abs(truth - estimate)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(gap == 0, 0.0, np.where(arm > 0, gap / arm, np.inf))


def conformal_factor(score: np.ndarray, level: float) -> float:
    """The split-conformal quantile of `score (n,)` (NaN left out, infinite scores counted): the
    ceil((n + 1) level)-th smallest; NaN when n is too small for the level (no calibration is fitted then)."""
    return conformal_quantile(score, level, keep_infinite=True)


def widened_arms(estimate: np.ndarray, low: np.ndarray, high: np.ndarray, error: float, factor: float,
                 bounds: tuple[float, float]) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """The calibrated interval's ends: each arm of the bootstrap interval (`low`, `high` about
    `estimate`, any shape) with the error added in quadrature, times the factor, within `bounds`."""
    lo = np.maximum(bounds[0], estimate - factor * np.hypot(estimate - low, error))
    hi = np.minimum(bounds[1], estimate + factor * np.hypot(high - estimate, error))
    return lo, hi


def widen(measure: str, estimate: float, interval: ClipInterval, calibration: HeadMeasureCalibration,
          level: float) -> ClipInterval:  # fmt: skip
    """The bootstrap interval of `measure` calibrated at `level` (`widened_arms`), and the
    `interval` column saying how."""
    if not np.isfinite(interval.low):
        return interval
    f = calibration.levels[level]
    low, high = widened_arms(np.float64(estimate), np.float64(interval.low), np.float64(interval.high),
                             calibration.error, f.factor, BOUNDS[measure])  # fmt: skip
    how = (f"calibrated: {interval.how}; each arm with a measurement error of {calibration.error:.3g} added in "
           f"quadrature, x{f.factor:.2f} (split conformal, {f.calibration_clips} calibration clips) for "
           f"{level:.0%}; held-out coverage {f.held_out_coverage:.1%} of {f.held_out_clips} synthetic 1-10 min clips "
           "(docs/clinical.md, Head)")  # fmt: skip
    return ClipInterval(float(low), float(high), interval.block, how)
