"""Calibrated per-joint 3D uncertainty of a lift.

For each lifted joint, `uncertainty_m` is the radius (metres) of the ball around the reported
root-relative position that holds the true joint with probability `coverage` (90 %). The
model is split-conformal, per joint j:

    radius_j = scale_j * (spread_j + floor_j)

where `spread_j` is the RMS distance of the K hypotheses' joint j from the reported one (0 with
one hypothesis), `floor_j` a fixed floor (the median spread on the calibration poses; 1 with one
hypothesis, so the radius is a per-joint constant) and `scale_j` the conformal quantile of
`error / (spread + floor)` on held-out poses. The constants are fitted by
`benchmarks/calibrate/calibrate_uncertainty.py` on poses no fold prior saw (never Test100) and hold only
for the prior and lifting settings they were fitted with: a calibration names the prior's
sha256 and the settings, and a lift with anything else reports no uncertainty (and says why)
rather than a number that was never checked.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from ..stats import require_quantile
from ..versioned_json import FileModel, ShippedFile
from .config import LiftConfig, calibration_settings, settings_match
from .result import joint_spread
from .solver import LiftResult

COVERAGE = 0.9  # the probability each radius is calibrated to hold
FORMAT = "zedo.uncertainty"
FORMAT_VERSION = 1


@dataclass(frozen=True)
class UncertaintyModel:
    prior_sha256: str
    settings: dict[str, Any]  # LiftConfig.to_dict() without _IRRELEVANT
    coverage: float
    joints: tuple[str, ...]
    floor_m: np.ndarray  # (J,)
    scale: np.ndarray  # (J,)
    provenance: dict[str, Any]  # data, folds, and the measured held-out coverage


class UncertaintyEntry(FileModel):
    """An `UncertaintyModel` in the file (floors and scales to 6 decimals): what `read_calibrations` validates and
    `write_calibrations` writes."""

    prior_sha256: str
    settings: dict[str, Any]
    coverage: float
    joints: list[str]
    floor_m: list[float]
    scale: list[float]
    provenance: dict[str, Any] = {}

    @classmethod
    def of(cls, m: UncertaintyModel) -> UncertaintyEntry:
        return cls(prior_sha256=m.prior_sha256, settings=m.settings, coverage=m.coverage, joints=list(m.joints),
                   floor_m=[round(float(v), 6) for v in m.floor_m], scale=[round(float(v), 6) for v in m.scale],
                   provenance=m.provenance)  # fmt: skip

    def value(self) -> UncertaintyModel:
        return UncertaintyModel(self.prior_sha256, dict(self.settings), self.coverage, tuple(self.joints),
                                np.asarray(self.floor_m, dtype=np.float64), np.asarray(self.scale, dtype=np.float64),
                                dict(self.provenance))  # fmt: skip


def radius_m(model: UncertaintyModel, spread: np.ndarray) -> np.ndarray:
    """Per-joint radii `(N, J)` from hypothesis spreads `(N, J)`."""
    return model.scale * (spread + model.floor_m)


def conformal_scale(scores: np.ndarray, coverage: float, joint: str = "a joint") -> float:
    """The split-conformal quantile of `scores (n,)`: the ceil((n + 1) coverage)-th smallest; `TooFewCases`
    where there are too few scores for `coverage` (no radius is written that no calibration backs)."""
    return require_quantile(scores, coverage, f"uncertainty calibration of {joint}")


def fit_model(
    error_m: np.ndarray, spread: np.ndarray, *, coverage: float, prior_sha256: str, cfg: LiftConfig,
    joints: tuple[str, ...], provenance: dict[str, Any],
) -> UncertaintyModel:  # fmt: skip
    """Fit floors and scales on held-out errors `(n, J)` (metres) and spreads `(n, J)`."""
    if cfg.hypotheses > 1:
        floor = np.nanmedian(spread, axis=0)
    else:
        floor = np.ones(error_m.shape[1])
    scale = np.array([conformal_scale(error_m[:, j] / (spread[:, j] + floor[j]), coverage, joints[j])
                      for j in range(error_m.shape[1])])  # fmt: skip
    return UncertaintyModel(prior_sha256, calibration_settings(cfg), coverage, joints, floor, scale, provenance)


_FILE = ShippedFile("uncertainty.json", FORMAT, FORMAT_VERSION, "models", "uncertainty calibration", UncertaintyEntry)


def bundled_calibrations_path() -> Path:
    return _FILE.bundled_path()


@functools.cache
def bundled_calibrations() -> tuple[UncertaintyModel, ...]:
    """The calibrations shipped with the package (none when the file is absent), read once a process."""
    return _FILE.read_bundled()


def read_calibrations(path: str | Path) -> list[UncertaintyModel]:
    """The models of a calibration file (format `zedo.uncertainty`, version 1)."""
    return _FILE.read(path)


def write_calibrations(path: str | Path, models: list[UncertaintyModel]) -> None:
    _FILE.write(path, models)


def find_model(
    models: Sequence[UncertaintyModel], prior_sha256: str, joints: tuple[str, ...], cfg: LiftConfig
) -> tuple[UncertaintyModel | None, str]:
    """The model calibrated for this prior and these settings, or None and why there is none."""
    mine = [m for m in models if m.prior_sha256 == prior_sha256 and m.joints == tuple(joints)]
    if not mine:
        return None, "no uncertainty calibration for this prior"
    wanted = calibration_settings(cfg)
    for m in mine:
        if settings_match(m.settings, wanted):
            return m, "calibrated"
    ks = sorted({m.settings.get("hypotheses", 1) for m in mine})
    return None, ("no uncertainty calibration for these lifting settings (calibrated: the default preset with "
                  f"--hypotheses {' or '.join(map(str, ks))})")  # fmt: skip


def attach_uncertainty(res: LiftResult, prior_sha256: str, joints: tuple[str, ...],
                       models: Sequence[UncertaintyModel]) -> LiftResult:  # fmt: skip
    """`res` with `uncertainty_m` filled from the model calibrated for its prior and settings
    (NaN where not lifted), or left None with `uncertainty_note` saying why."""
    model, note = find_model(models, prior_sha256, joints, res.config)
    if model is None:
        return replace(res, uncertainty_m=None, uncertainty_note=note)
    spread = joint_spread(res.hypotheses, res.poses_root_relative)
    if res.hypotheses is not None:  # an instance with fewer usable hypotheses than calibrated for
        usable = np.isfinite(res.hypotheses).all(axis=(2, 3)).sum(1)
        spread = np.where((usable == res.config.hypotheses)[:, None], spread, np.nan)
    radius = radius_m(model, spread)
    radius[~res.lifted] = np.nan
    return replace(res, uncertainty_m=radius, uncertainty_coverage=model.coverage,
                   uncertainty_note=f"calibrated {model.coverage:.0%} radius")  # fmt: skip
