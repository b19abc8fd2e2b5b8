"""`analyse`: a zedo result -> every measure per frame and person, as tidy rows.

    res = read_result("clip.zedo.json")
    a = analyse(res, AnalysisSettings(threshold_deg=28.0, fps=30.0))
    a.rows          # one Row per (frame, person, measure), then the per-clip features

Rows follow the CSV's columns (COLUMNS): per lifted person, the four symmetry angles
(`symmetry_upper_arm_deg`, `symmetry_forearm_deg`, `symmetry_thigh_deg`,
`symmetry_shank_deg`) with their call, the paper's band of each (`symmetry_<pair>_band`), and
the twelve joint angles; then, for a sequence (an fps from the settings or the result), the
movement features of each person's clip (frame_index, image_id and file_name empty).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..data.skeleton import Skeleton
from ..errors import ConfigError, InputFormatError
from ..formats.result_reader import ResultPoses
from .geometry import require_joints
from .joint_angles import ANGLE_BASES, ANGLE_NAMES, SIDES, angle_name, joint_angles
from .movement import MIN_FRAMES, left_right_correlation, series_features
from .symmetry import (
    DEFAULT_THRESHOLD_DEG,
    PAIRS,
    SYMMETRY_JOINTS,
    measure_name,
    symmetry_angles,
    symmetry_band,
    symmetry_call,
)
from .uncertainty import DEFAULT_SAMPLES, sample_intervals

COLUMNS = ("frame_index", "image_id", "file_name", "person", "measure", "value", "unit", "low_90", "high_90",
           "call", "interval")  # fmt: skip
SYMMETRY_NAMES = tuple(measure_name(p) for p in PAIRS)
# The `interval` column: why low_90 / high_90 are (or are not) filled.
INTERVAL_SAMPLED = "from_uncertainty_m"
INTERVAL_NONE = "no_uncertainty_in_result"
INTERVAL_UNKNOWN_RADIUS = "radius_unknown"
INTERVAL_CLIP = "not_for_clip_features"
NO_UNCERTAINTY_NOTE = ("no per-joint uncertainty (uncertainty_m) in the result: no 90 % intervals; "
                       "symmetry calls are symmetric/asymmetric only, never uncertain")  # fmt: skip


@dataclass(frozen=True)
class AnalysisSettings:
    """What `zedo analyze` lets a user choose."""

    threshold_deg: float = DEFAULT_THRESHOLD_DEG
    fps: float | None = None  # overrides the fps recorded in the result
    samples: int = DEFAULT_SAMPLES
    seed: int = 0

    def __post_init__(self) -> None:
        if not 0.0 <= self.threshold_deg <= 180.0:
            raise ConfigError(f"--symmetry-threshold must be in [0, 180] degrees, got {self.threshold_deg}")
        if self.fps is not None and not self.fps > 0:
            raise ConfigError(f"--fps must be > 0, got {self.fps}")
        if self.samples < 100:
            raise ConfigError(f"--samples must be at least 100, got {self.samples}")


@dataclass
class Row:
    """One line of the tidy table (see COLUMNS)."""

    frame_index: int | None
    image_id: int | str | None
    file_name: str | None
    person: int
    measure: str
    value: float
    unit: str
    low_90: float = np.nan
    high_90: float = np.nan
    call: str = ""
    interval: str = ""

    def as_list(self) -> list[Any]:
        return [getattr(self, c) for c in COLUMNS]


@dataclass
class Analysis:
    """The measures of one result: per-instance arrays (rows of `result` that were lifted) and rows."""

    result: ResultPoses
    settings: AnalysisSettings
    index: np.ndarray  # (M,) rows of `result` analysed (the lifted persons)
    values: dict[str, np.ndarray]  # measure -> (M,) degrees
    intervals: dict[str, tuple[np.ndarray, np.ndarray]] | None  # measure -> (low, high) (M,), or None
    fps: float | None
    fps_source: str  # "option", "result" or "none"
    rows: list[Row] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)

    @property
    def uncertainty_available(self) -> bool:
        return self.intervals is not None

    @property
    def is_sequence(self) -> bool:
        return self.fps is not None


def all_measures(poses: np.ndarray, skeleton: Skeleton) -> dict[str, np.ndarray]:
    """Symmetry angles and joint angles of poses `(..., J, 3)`, by measure name."""
    return {**symmetry_angles(poses, skeleton), **joint_angles(poses, skeleton)}


def measure_ranges() -> dict[str, tuple[float, float]]:
    """The values each frame measure can take, in degrees (intervals are clipped to them)."""
    ranges = dict.fromkeys(SYMMETRY_NAMES, (0.0, 180.0))
    for name in ANGLE_NAMES:
        if "abduction" in name:
            ranges[name] = (-90.0, 90.0)
        elif "hip_flexion" in name or "shoulder_flexion" in name:
            ranges[name] = (-90.0, 270.0)
        else:
            ranges[name] = (0.0, 180.0)
    return ranges


def analyse(result: ResultPoses, settings: AnalysisSettings | None = None) -> Analysis:
    """Every measure of every lifted person of `result`, with 90 % intervals where the result
    carries `uncertainty_m`; movement features per person when an fps is known."""
    settings = settings or AnalysisSettings()
    require_joints(result.skeleton, SYMMETRY_JOINTS, result.source)
    index = np.flatnonzero(result.lifted & np.isfinite(result.poses).any((1, 2)))
    if not len(index):
        raise InputFormatError(f"{result.source}: no lifted person in the result: nothing to analyse")
    poses = result.poses[index]
    values = all_measures(poses, result.skeleton)
    intervals = None
    if result.uncertainty_m is not None:
        intervals = sample_intervals(poses, result.uncertainty_m[index],
                                     lambda p: all_measures(p, result.skeleton),
                                     ranges=measure_ranges(), samples=settings.samples, seed=settings.seed)  # fmt: skip
    fps, fps_source = (settings.fps, "option") if settings.fps is not None else (result.fps, "result")
    if fps is None:
        fps_source = "none"
    a = Analysis(result, settings, index, values, intervals, fps, fps_source)
    if intervals is None:
        a.notes.append(NO_UNCERTAINTY_NOTE)
    else:
        a.notes.append(f"90 % intervals from the result's uncertainty_m ({settings.samples} samples per person, "
                       f"seed {settings.seed}); a call whose interval straddles the threshold: uncertain")  # fmt: skip
    if len(index) < len(result):
        a.notes.append(f"{len(result) - len(index)} of {len(result)} persons were not lifted and are left out")
    if fps is None:
        a.notes.append("no fps (neither --fps nor recorded by zedo lift --fps): frames are analysed as separate "
                       "images, without movement features")  # fmt: skip
    a.rows = _frame_rows(a)
    if fps is not None:
        a.rows += _clip_rows(a)  # reads the frame rows' calls
    return a


def _frame_rows(a: Analysis) -> list[Row]:
    res, thr = a.result, a.settings.threshold_deg
    rows: list[Row] = []
    for k, i in enumerate(a.index):
        head = (int(res.frame_index[i]), res.image_ids[i], res.file_names[i], int(res.person[i]))
        for name in (*SYMMETRY_NAMES, *ANGLE_NAMES):
            v = float(a.values[name][k])
            low = high = np.nan
            if a.intervals is None:
                how = INTERVAL_NONE
            else:
                low, high = (float(x[k]) for x in a.intervals[name])
                how = INTERVAL_SAMPLED if np.isfinite(low) else INTERVAL_UNKNOWN_RADIUS
            call = symmetry_call(v, thr, low, high) if name in SYMMETRY_NAMES else ""
            rows.append(Row(*head, name, v, "deg", low, high, call, how))
            if name in SYMMETRY_NAMES:
                band = name.replace("_deg", "_band")
                rows.append(
                    Row(*head, band, symmetry_band(v), "band", symmetry_band(low), symmetry_band(high), "", how)
                )
    return rows


def _clip_rows(a: Analysis) -> list[Row]:
    res, fps = a.result, float(a.fps or 0.0)
    rows: list[Row] = []
    people = res.person[a.index]
    frames = res.frame_index[a.index]
    for p in sorted(set(people.tolist())):
        sel = people == p
        if sel.sum() < MIN_FRAMES:
            a.notes.append(f"person {p}: fewer than {MIN_FRAMES} lifted frames, no movement features")
            continue

        def add(measure: str, value: float, unit: str, p: int = p) -> None:
            rows.append(Row(None, None, None, p, measure, value, unit, interval=INTERVAL_CLIP))

        for name in ANGLE_NAMES:
            feats = series_features(frames[sel], a.values[name][sel], fps)
            stem = name.removesuffix("_deg")
            add(f"{stem}_median_abs_velocity_deg_s", feats["median_abs_velocity"], "deg/s")
            add(f"{stem}_abs_velocity_iqr_deg_s", feats["abs_velocity_iqr"], "deg/s")
            add(f"{stem}_range_deg", feats["range"], "deg")
        for base in ANGLE_BASES:
            left, right = (a.values[angle_name(side, base)][sel] for side in SIDES)
            add(f"{base}_left_right_correlation", left_right_correlation(left, right), "r")
        for name in SYMMETRY_NAMES:
            calls = [r.call for r in a.rows if r.measure == name and r.person == p and r.call]
            share = calls.count("symmetric") / len(calls) if calls else np.nan
            add(name.replace("_deg", "_fraction_symmetric"), share, "fraction")
    return rows


def summary(a: Analysis) -> dict[str, dict[str, float | int]]:
    """Per frame measure: count, mean, median, min, max; for symmetry also the calls and bands."""
    out: dict[str, dict[str, float | int]] = {}
    for name in (*SYMMETRY_NAMES, *ANGLE_NAMES):
        v = a.values[name][np.isfinite(a.values[name])]
        stats: dict[str, float | int] = {"count": int(len(v))}
        if len(v):
            stats.update(mean=float(v.mean()), median=float(np.median(v)), min=float(v.min()), max=float(v.max()))
        if name in SYMMETRY_NAMES:
            calls = [r.call for r in a.rows if r.measure == name and r.frame_index is not None]
            stats.update({c: calls.count(c) for c in ("symmetric", "asymmetric", "uncertain")})
            bands = [symmetry_band(x) for x in v]
            stats.update({f"band_{b}": bands.count(float(b)) for b in (1, 2, 3)})
        out[name] = stats
    return out
