"""`analyse`: a zedo result -> every measure per frame and person, as tidy rows.

    res = read_result("clip.zedo.json")
    a = analyse(res, AnalysisSettings(threshold_deg=28.0, fps=30.0))
    a.rows          # one Row per (frame, person, measure), then the per-clip features

Rows follow the CSV's columns (COLUMNS): per lifted person, the four symmetry angles
(`symmetry_upper_arm_deg`, `symmetry_forearm_deg`, `symmetry_thigh_deg`,
`symmetry_shank_deg`) with their call, the paper's band of each (`symmetry_<pair>_band`), and
the twelve joint angles; then per pose the head's `head_tilt_deg` and `head_turn` (from the input's
2D face points and shoulders, `analysis.head`); then, for a sequence (an fps from the settings or
the result), the movement features of each person's clip (frame_index, image_id and file_name
empty), its head-turn shares and median tilt with block bootstrap intervals, then its
published 2D features (Chambers et al. 2020) and `3d_` features (`analysis.clip_features`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from ..data.skeleton import Skeleton, root_point
from ..errors import ConfigError, InputFormatError, plural
from ..formats.readers.result import ResultPoses
from ..stats import TOO_FEW_CASES
from .clip.clip_features import clip_features
from .clip.movement import MIN_FRAMES, angular_velocity, movement_values
from .pose.geometry import require_joints
from .pose.head import (
    TILT,
    TURN,
    TURN_CALLS,
    HeadFrames,
    HeadSettings,
    face_points,
    head_clip,
    head_frames,
    shoulder_points,
)
from .pose.joint_angles import (
    ANGLE_BASES,
    ANGLE_NAMES,
    CIRCULAR_ANGLES,
    FLEXION_RANGE_DEG,
    joint_angles,
)
from .pose.symmetry import (
    CALLS,
    DEFAULT_THRESHOLD_DEG,
    PAIRS,
    SYMMETRY_JOINTS,
    measure_name,
    symmetry_angles,
    symmetry_bands,
    symmetry_calls,
)
from .table import COLUMNS, Block, Row, clip_row, rows_block
from .uncertainty.calibration import (
    DEFAULT_CALL_LEVEL,
    DEFAULT_LEVEL,
    LEVELS,
    Assignment,
    MeasureCalibration,
    assign_calibrations,
    backing_note,
    bundled_calibrations,
    camera_stand_in,
    find_calibration,
    held_out_note,
    measure_joints,
)
from .uncertainty.clip_share import Share, block_frames, probability_above, share_interval
from .uncertainty.domain import outside_calibration, without_outside
from .uncertainty.share_calibration import calibrated_share

SYMMETRY_NAMES = tuple(measure_name(p) for p in PAIRS)
# How a frame measure's interval was obtained, "code: note" (the `interval` and `interval_note` columns, table.py)
INTERVAL_CALIBRATED = "calibrated"  # measure-level split conformal (analysis.calibration)
INTERVAL_FILLED = "calibrated_filled"  # the calibration's model of such cases, wider; the note names the joints
INTERVAL_CLIP = "not_for_clip_features"
INTERVAL_CLIP_MEDIAN = "median_of_frame_interval_ends"
DEFAULT_MAX_VELOCITY_DEG_S = 500.0
FLAG_TOO_FAST = "too_fast"


@dataclass(frozen=True)
class AnalysisSettings:
    """What `zedo analyze` lets a user choose."""

    threshold_deg: float = DEFAULT_THRESHOLD_DEG
    fps: float | None = None  # overrides the fps recorded in the result
    level: float = DEFAULT_LEVEL  # the intervals' coverage
    call_level: float = DEFAULT_CALL_LEVEL  # the symmetry calls use the interval of this level
    max_velocity_deg_s: float = DEFAULT_MAX_VELOCITY_DEG_S  # faster joint-angle changes are flagged
    head: HeadSettings = field(default_factory=HeadSettings)  # head tilt and turn (analysis.head)

    def __post_init__(self) -> None:
        if not 0.0 <= self.threshold_deg <= 180.0:
            raise ConfigError(f"--symmetry-threshold must be in [0, 180] degrees, got {self.threshold_deg}")
        if self.fps is not None and not self.fps > 0:
            raise ConfigError(f"--fps must be > 0, got {self.fps}")
        if self.level not in LEVELS:
            raise ConfigError(f"--level must be one of {', '.join(map(str, LEVELS))}, got {self.level}")
        if self.call_level not in LEVELS:
            raise ConfigError(f"--call-level must be one of {', '.join(map(str, LEVELS))}, got {self.call_level}")
        if not self.max_velocity_deg_s > 0:
            raise ConfigError(f"--max-angular-velocity must be > 0 deg/s, got {self.max_velocity_deg_s}")


@dataclass(frozen=True)
class Analysis:
    """The measures of one result, frozen: per-pose arrays (rows of `result` that were lifted) by measure, the
    per-clip rows, and notes; the frame rows are built from the arrays when asked for (`rows`, `blocks`)."""

    result: ResultPoses
    settings: AnalysisSettings
    index: np.ndarray  # (M,) rows of `result` analysed (the lifted persons)
    values: dict[str, np.ndarray]  # measure -> (M,) degrees: the estimate (calibrated where a calibration holds)
    raw_values: dict[str, np.ndarray]  # measure -> (M,) degrees: the measure of the reported pose
    intervals: dict[str, tuple[np.ndarray, np.ndarray]]  # measure -> (low, high) (M,), NaN where none
    call_intervals: dict[str, tuple[np.ndarray, np.ndarray]]  # the same at settings.call_level
    interval_how: dict[str, list[str]]  # measure -> (M,) the `interval` column
    calibration_note: str  # "calibrated" or why no measure calibration holds
    fps: float | None
    fps_source: str  # "option", "result" or "none"
    too_fast: dict[str, np.ndarray] = field(default_factory=dict)  # angle -> (M,) bool
    calls: dict[str, np.ndarray] = field(default_factory=dict)  # symmetry measure -> (M,) its call ("": unknown)
    clip_rows: tuple[Row, ...] = ()  # the per-clip rows (movement, features, comparison)
    notes: tuple[str, ...] = ()
    comparisons: tuple[Any, ...] = ()  # compare.PersonComparison per person, with --norms
    reference: Any = None  # the reference of typical infants compared with (norms.Norms), with --norms
    assignment: Assignment | None = None  # which measure calibration holds for each analysed pose
    clip_calibration: MeasureCalibration | None = None  # the clip-scope calibration found for the result
    # symmetry measure -> (M,) the probability that the true angle exceeds the threshold (NaN: no calibration)
    probabilities: dict[str, np.ndarray] = field(default_factory=dict)
    head: HeadFrames | None = None  # the head measures of the analysed poses (from the input's 2D)

    def frame_blocks(self) -> list[Block]:
        """The frame rows as columns, built from the arrays: the body's measures, then the head's."""
        return [_frame_block(self)] if self.head is None else [_frame_block(self), _head_block(self)]

    def blocks(self) -> list[Block]:
        """The tidy table as columns: the frame rows, then the clip rows."""
        return self.frame_blocks() + ([rows_block(self.clip_rows)] if self.clip_rows else [])

    @property
    def rows(self) -> list[Row]:
        """One Row per (frame, person, measure), built when asked for, then the per-clip rows."""
        return [row for block in self.frame_blocks() for row in block.rows()] + list(self.clip_rows)

    def columns(self) -> dict[str, list[Any]]:
        """The tidy table by column (COLUMNS -> one value per row): the CSV's rows, with None and
        NaN where a value is unknown."""
        rows = self.rows
        return {c: [getattr(r, c) for r in rows] for c in COLUMNS}

    def to_pandas(self) -> Any:
        """The tidy table as a pandas DataFrame: the CSV's columns, one row per frame, person and
        measure, then the per-clip features (frame_index <NA>). pandas is an optional extra."""
        try:
            import pandas as pd
        except ImportError:
            raise ImportError(
                "Analysis.to_pandas() needs pandas, an optional extra of zedo: pip install -e '.[pandas]' in a zedo "
                "checkout "
                "(Analysis.columns() gives the same table as plain lists)"
            ) from None
        return pd.DataFrame(self.columns(), columns=list(COLUMNS)).astype({"frame_index": "Int64"})

    @property
    def uncertainty_available(self) -> bool:
        """Whether any pose has calibrated intervals (`calibration_note` is "calibrated" when every pose has)."""
        return self.calibration_note == INTERVAL_CALIBRATED or (self.assignment is not None and self.assignment.any)

    @property
    def is_sequence(self) -> bool:
        return self.fps is not None


def all_measures(poses: np.ndarray, skeleton: Skeleton) -> dict[str, np.ndarray]:
    """Symmetry angles and joint angles of poses `(..., J, 3)`, by measure name."""
    return {**symmetry_angles(poses, skeleton), **joint_angles(poses, skeleton)}


def measure_ranges() -> dict[str, tuple[float, float]]:
    """The values each frame measure can take, in degrees (estimates and intervals stay in them)."""
    ranges = dict.fromkeys(SYMMETRY_NAMES, (0.0, 180.0))
    for name in ANGLE_NAMES:
        if "abduction" in name:
            ranges[name] = (-90.0, 90.0)
        elif name in CIRCULAR_ANGLES:
            ranges[name] = FLEXION_RANGE_DEG
        else:
            ranges[name] = (0.0, 180.0)
    return ranges


def calibrated_measures(
    poses: np.ndarray, observed: np.ndarray, skeleton: Skeleton, calibration: MeasureCalibration | None,
    why_not: str, levels: tuple[float, ...], *, assignment: Assignment | None = None,
) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray], list[dict[str, tuple[np.ndarray, np.ndarray]]],
           dict[str, list[str]]]:  # fmt: skip
    """Raw measures, estimates, intervals at each of `levels` and the `interval` column of poses `(M, J, 3)`
    (camera axes) with their observed joints `(M, J)`, under `calibration` (None: `why_not`), or pose by
    pose under `assignment` (which then replaces both)."""

    def measures(p: np.ndarray) -> dict[str, np.ndarray]:
        return all_measures(p, skeleton)

    raw = measures(poses)
    m = len(poses)
    if assignment is None:
        cals = () if calibration is None else (calibration,)
        assignment = Assignment(cals, np.full(m, 0 if cals else -1), np.full(m, "" if cals else why_not, object))
    estimates = {k: v.copy() for k, v in raw.items()}
    nan = np.full(m, np.nan)
    intervals = [{k: (nan.copy(), nan.copy()) for k in raw} for _ in levels]
    base_how = np.where(assignment.index >= 0, INTERVAL_CALIBRATED, "none: " + assignment.why_not.astype(str))
    how = {k: base_how.astype(object) for k in raw}
    uses = measure_joints(skeleton, measures, list(raw))
    ranges = measure_ranges()
    for name, v in raw.items():
        filled = ~observed[:, uses[name]]
        for k in np.flatnonzero(~np.isfinite(v) | filled.any(1)):  # only the cases without an interval
            if not np.isfinite(v[k]):
                known = np.isfinite(poses[k]).all(-1)
                missing = [j for j, u, ok in zip(skeleton.joints, uses[name], known, strict=True) if u and not ok]
                how[name][k] = "none: joint missing: " + ", ".join(missing) if missing else "none: undefined here"
            elif filled[k].any() and assignment.index[k] >= 0:  # else the pose's own reason: no calibration holds it
                names = [j for j, u in zip(skeleton.joints, uses[name], strict=True) if u]
                gone = [j for j, f in zip(names, filled[k], strict=True) if f]
                how[name][k] = "none: joint filled by the prior (not calibrated): " + ", ".join(gone)
        usable = np.isfinite(v) & ~filled.any(1)
        for c, cal in enumerate(assignment.calibrations):
            ok = usable & (assignment.index == c)
            if name not in cal.measures:
                how[name][ok] = f"none: the measure calibration has no {name}"
                continue
            apply = [(ok, cal.measures[name])]
            if name in cal.filled:  # cases with a joint the prior filled: their own, wider model
                gaps = np.isfinite(v) & filled.any(1) & (assignment.index == c)
                how[name][gaps] = [h.replace("none: joint filled by the prior (not calibrated)", INTERVAL_FILLED)
                                   for h in how[name][gaps]]  # fmt: skip
                apply.append((gaps, cal.filled[name]))
            for sel, model in apply:
                if not sel.any():
                    continue
                est = model.estimate(v[sel])
                lo_r, hi_r = ranges[name]
                estimates[name][sel] = np.clip(est, lo_r, hi_r)
                for level, at_level in zip(levels, intervals, strict=True):
                    low, high = model.interval(est, v[sel], level)
                    at_level[name][0][sel] = np.clip(low, lo_r, hi_r)
                    at_level[name][1][sel] = np.clip(high, lo_r, hi_r)
                    sparse = np.flatnonzero(sel)[np.isnan(low) | np.isnan(high)]
                    how[name][sparse] = f"none: {TOO_FEW_CASES}"
    return raw, estimates, intervals, {k: list(v) for k, v in how.items()}


def no_calibration_note(why: str) -> str:
    """The analysis note of a result that no calibration holds for (`why`); the report's decisions state it."""
    return f"no calibrated intervals: {why}; every symmetry call is uncertain (no calibration backs one)"


def pose_cameras(result: ResultPoses, index: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The root depth (metres from the camera) and focal length (pixels, the mean of fx and fy) of each
    pose `index (M,)` of `result`; NaN where the result states neither its camera-frame position nor its camera."""
    if result.coordinate_frame == "camera":
        depth = root_point(result.poses[index], result.skeleton)[:, 2]
    elif result.root_translation is not None:
        depth = result.root_translation[index, 2]
    else:
        depth = np.full(len(index), np.nan)
    cams = result.cameras
    focal = np.array([np.nan if cams is None or cams[i] is None else (cams[i].fx + cams[i].fy) / 2 for i in index])
    return depth, focal.reshape(-1)


def analyse(
    result: ResultPoses, settings: AnalysisSettings | None = None,
    calibrations: Sequence[MeasureCalibration] | None = None,
) -> Analysis:  # fmt: skip
    """Every measure of every lifted person of `result`: the estimate, its calibrated interval where
    a measure calibration holds for the result's prior, settings, temporal mode and camera
    (`calibrations`: default the bundled ones), the symmetry calls, and movement features per
    person when an fps is known."""
    settings = settings or AnalysisSettings()
    require_joints(result.skeleton, SYMMETRY_JOINTS, result.source)
    index = np.flatnonzero(result.lifted & np.isfinite(result.poses).any((1, 2)))
    if not len(index):
        raise InputFormatError(f"{result.source}: no lifted person in the result: nothing to analyse")
    models = bundled_calibrations() if calibrations is None else calibrations
    cameras = pose_cameras(result, index)
    assignment = assign_calibrations(models, result.params, result.skeleton.joints, *cameras)
    outside = outside_calibration(result, index)
    assignment = without_outside(assignment, outside)  # a track unlike the calibration clips: no interval, and why
    note = assignment.note()
    raw, values, (intervals, call_intervals), how = calibrated_measures(
        result.poses[index], result.observed[index], result.skeleton, None, note,
        (settings.level, settings.call_level), assignment=assignment)  # fmt: skip
    fps, fps_source = (settings.fps, "option") if settings.fps is not None else (result.fps, "result")
    if fps is None:
        fps_source = "none"
    a = Analysis(result, settings, index, values, raw, intervals, call_intervals, how, note, fps, fps_source,
                 assignment=assignment)  # fmt: skip
    notes: list[str] = []
    if not assignment.any:
        notes.append(no_calibration_note(note))
    else:
        out = int((assignment.index < 0).sum())
        if out:
            notes.append(f"{out} of {len(index)} poses have no calibrated intervals ({note}); their symmetry calls "
                           "are uncertain")  # fmt: skip
        used = assignment.used()
        notes.extend(backing_note(c) for c in used)
        notes.extend(dict.fromkeys(held_out_note(c) for c in used))  # ranges of one fit share their figures
        if assignment.stand_in:
            notes.append(f"{assignment.stand_in} of {len(index)} poses: the stated camera lies outside the known "
                           "cameras' calibrated range, so the pseudo camera's calibration stands in (docs/clinical.md, "
                           "\"Stated camera or not\")")  # fmt: skip
        sources = (c.provenance.get("data", "see the calibration file") for c in used)
        data = "; ".join(dict.fromkeys(str(x) for x in sources))
        side = (1 - settings.call_level) / 2
        notes.append(f"{settings.level:.0%} intervals and estimates calibrated at the level of each measure on "
                       f"held-out lifts ({data}); a call is symmetric or asymmetric only when the "
                       f"{settings.call_level:.0%} interval (call_low, call_high) lies on one side of the threshold, "
                       f"each of whose ends misses the truth at most {side:.0%} of the time")  # fmt: skip
    if len(index) < len(result):
        notes.append(f"{len(result) - len(index)} of {len(result)} persons were not lifted and are left out")
    if fps is None:
        notes.append("no fps (neither --fps nor recorded by zedo lift --fps): frames are analysed as separate "
                       "images, without movement features")  # fmt: skip
    else:
        a = replace(a, too_fast=_too_fast(a, fps))
        flagged = sum(int(v.sum()) for v in a.too_fast.values())
        if flagged:
            bound = settings.max_velocity_deg_s
            notes.append(f"{flagged} joint-angle values change faster than {bound:g} deg/s from the previous "
                           "frame: flagged too_fast and left out of the movement features")  # fmt: skip
    calls = {name: symmetry_calls(values[name], settings.threshold_deg, *call_intervals[name])
             for name in SYMMETRY_NAMES}  # fmt: skip
    a = replace(a, probabilities=_probabilities(a), calls=calls)
    head, head_why = _measure_head(a)
    if head_why is not None:
        notes.append(f"no head measures: {head_why}")
    a = replace(a, head=head)
    if fps is not None:
        clip_rows = _clip_rows(a, notes) + _head_clip_rows(a, head_why)
        features, clip_calibration = _clip_feature_rows(a, models, cameras, outside, notes)
        a = replace(a, clip_rows=tuple(clip_rows + features), clip_calibration=clip_calibration)
    return replace(a, notes=tuple(notes))


def _clip_feature_rows(
    a: Analysis, models: Sequence[MeasureCalibration], cameras: tuple[np.ndarray, np.ndarray], outside: np.ndarray,
    notes: list[str],
) -> tuple[list[Row], MeasureCalibration | None]:  # fmt: skip
    """The published 2D and the `3d_` features of each track, the latter under the clip-scope calibration that
    holds (returned, named in `notes`)."""
    res = a.result
    clip_cal, clip_why = find_calibration(models, res.params, res.skeleton.joints, scope="clips")
    if clip_cal is not None:
        notes.append(backing_note(clip_cal))
        notes.append(held_out_note(clip_cal))
    stand_in = camera_stand_in(models, res.params, res.skeleton.joints, scope="clips")
    features = clip_features(res, a.index, float(a.fps or 0.0), clip_cal, clip_why, a.settings.level, cameras, outside,
                             stand_in)  # fmt: skip
    level = a.settings.level
    rows = [clip_row(f.person, f.measure, f.value, f.unit, f.interval, level, f.low, f.high, f.raw_value)
            for f in features]  # fmt: skip
    return rows, clip_cal


def _measure_head(a: Analysis) -> tuple[HeadFrames, str | None]:
    """The head measures of the analysed poses from the input's face points and shoulders, the lift's
    --min-confidence applying to the face points too, and why there are none (None: there are)."""
    res = a.result
    min_conf = res.lift_params.min_confidence
    settings = a.settings.head
    if min_conf is not None and min_conf > settings.min_confidence:
        settings = replace(settings, min_confidence=min_conf)
    face, why = face_points(res, a.index, settings.min_confidence)
    if why is None and res.keypoints_2d is None:
        why = "the result does not carry the input's 2D keypoints (the shoulders')"
    return head_frames(face, shoulder_points(res, a.index), settings, why), why


def _head_block(a: Analysis) -> Block:
    """`head_tilt_deg` and `head_turn` of every analysed pose (after the body's frame rows)."""
    h = a.head
    assert h is not None
    tilt = {"measure": TILT, "value": h.tilt_deg, "unit": "deg", "how": np.asarray(h.tilt_how, dtype=object),
            "flag": np.asarray(h.tilt_flag, dtype=object)}  # fmt: skip
    turn = {"measure": TURN, "value": h.turn_deg, "unit": "deg", "call": np.asarray(h.turn_call, dtype=object),
            "how": np.asarray(h.turn_how, dtype=object)}  # fmt: skip
    return Block(len(a.index), _pose_keys(a), (tilt, turn), a.settings.level)


def _head_clip_rows(a: Analysis, why: str | None) -> list[Row]:
    """Per person track: the head-turn shares and the median tilt, with calibrated intervals at --level."""
    assert a.head is not None and a.fps is not None
    people, frames = a.result.person[a.index], a.result.frame_index[a.index]
    rows: list[Row] = []
    for p in sorted(set(people.tolist())):
        sel = np.flatnonzero(people == p)
        sel = sel[np.argsort(frames[sel], kind="stable")]
        track = HeadFrames(*(getattr(a.head, f)[sel] for f in HeadFrames.__dataclass_fields__))
        for stat in head_clip(frames[sel], track, a.fps, a.settings.head, why, level=a.settings.level):
            i = stat.interval
            rows.append(clip_row(p, stat.measure, stat.value, stat.unit, i.how, a.settings.level, i.low, i.high))
    return rows


def _too_fast(a: Analysis, fps: float) -> dict[str, np.ndarray]:
    """Per joint angle, `(M,)`: the value changed faster than the bound since the person's previous known frame."""
    people, frames = a.result.person[a.index], a.result.frame_index[a.index]
    out = {}
    for name in ANGLE_NAMES:
        flags = np.zeros(len(a.index), bool)
        for p in np.unique(people):
            sel = np.flatnonzero(people == p)
            sel = sel[np.argsort(frames[sel], kind="stable")]
            theta = a.values[name][sel]
            known = sel[np.isfinite(theta)]
            if len(known) < 2:
                continue
            speed = np.abs(angular_velocity(frames[known], a.values[name][known], fps))
            flags[known[1:]] = speed > a.settings.max_velocity_deg_s
        out[name] = flags
    return out


def probability_name(name: str) -> str:
    """`symmetry_upper_arm_probability_asymmetric` etc.: the frame row of a symmetry measure's probability."""
    return name.removesuffix("_deg") + "_probability_asymmetric"


def _probabilities(a: Analysis) -> dict[str, np.ndarray]:
    """Per symmetry measure `(M,)`: each calibrated pose's probability of a true angle above the threshold."""
    out = {}
    assignment = a.assignment
    for name in SYMMETRY_NAMES:
        p = np.full(len(a.index), np.nan)
        calibrated = np.isfinite(a.intervals[name][0])
        filled = np.char.startswith(np.array(a.interval_how[name], dtype=str), INTERVAL_FILLED)
        if assignment is not None:
            for c, cal in enumerate(assignment.calibrations):
                for sel, models in ((calibrated & ~filled, cal.measures), (calibrated & filled, cal.filled)):
                    sel = sel & (assignment.index == c)
                    if sel.any() and name in models:
                        p[sel] = probability_above(models[name], a.raw_values[name][sel], a.settings.threshold_deg)
        out[name] = p
    return out


def _pose_keys(a: Analysis) -> dict[str, np.ndarray]:
    """The shared columns of the frame rows: one value per analysed pose."""
    res = a.result
    image_ids, file_names = np.empty(len(a.index), object), np.empty(len(a.index), object)
    image_ids[:] = [res.image_ids[i] for i in a.index]
    file_names[:] = [res.file_names[i] for i in a.index]
    return {"frame_index": res.frame_index[a.index].astype(np.int64), "image_id": image_ids, "file_name": file_names,
            "person": res.person[a.index].astype(np.int64)}  # fmt: skip


def _frame_block(a: Analysis) -> Block:
    """Per pose: each symmetry angle with its call, band and probability asymmetric, then the joint angles."""
    cells: list[dict[str, Any]] = []
    for name in (*SYMMETRY_NAMES, *ANGLE_NAMES):
        v, raw, (low, high) = a.values[name], a.raw_values[name], a.intervals[name]
        how = np.array(a.interval_how[name], dtype=object)
        cell = {"measure": name, "value": v, "unit": "deg", "low": low, "high": high, "how": how,
                "raw_value": raw}  # fmt: skip
        if name in a.too_fast:
            cell["flag"] = np.where(a.too_fast[name], FLAG_TOO_FAST, "").astype(object)
        cells.append(cell)
        if name in SYMMETRY_NAMES:
            known = np.isfinite(v)
            c_low, c_high = (np.where(known, x, np.nan) for x in a.call_intervals[name])
            cell.update(call=a.calls[name], call_low=c_low, call_high=c_high)
            cells.append({"measure": name.replace("_deg", "_band"), "value": symmetry_bands(v), "unit": "band",
                          "low": symmetry_bands(low), "high": symmetry_bands(high), "how": how,
                          "raw_value": symmetry_bands(raw)})  # fmt: skip
            cells.append({"measure": probability_name(name), "value": a.probabilities[name], "unit": "probability",
                          "how": how})  # fmt: skip
    return Block(len(a.index), _pose_keys(a), tuple(cells), a.settings.level)


def _clip_rows(a: Analysis, notes: list[str]) -> list[Row]:
    res, fps = a.result, float(a.fps or 0.0)
    rows: list[Row] = []
    people = res.person[a.index]
    frames = res.frame_index[a.index]
    for p in sorted(set(people.tolist())):
        sel = people == p
        if sel.sum() < MIN_FRAMES:
            notes.append(f"person {p}: fewer than {MIN_FRAMES} lifted frames, no movement features")
            continue

        def add(measure: str, value: float, unit: str, low: float = np.nan, high: float = np.nan,
                how: str = INTERVAL_CLIP, p: int = p, raw: float = np.nan) -> None:  # fmt: skip
            rows.append(clip_row(p, measure, value, unit, how, a.settings.level, low, high, raw))

        measured = movement_values(frames, sel, fps, estimates=a.values, own=a.raw_values, too_fast=a.too_fast)
        for name in ANGLE_NAMES:
            stem = name.removesuffix("_deg")
            for suffix, unit in (("_median_abs_velocity_deg_s", "deg/s"), ("_abs_velocity_iqr_deg_s", "deg/s"),
                                 ("_range_deg", "deg")):  # fmt: skip
                add(stem + suffix, measured[stem + suffix], unit)
            add(f"{stem}_frames_too_fast", float((sel & a.too_fast.get(name, False)).sum()), "frames")
        for base in ANGLE_BASES:
            add(f"{base}_left_right_correlation", measured[f"{base}_left_right_correlation"], "r")
        for name in SYMMETRY_NAMES:
            calls = a.calls[name][sel]
            calls = calls[calls != ""]
            stem = name.removesuffix("_deg")
            for call in CALLS:
                share = float((calls == call).sum()) / len(calls) if len(calls) else np.nan
                add(f"{stem}_fraction_{call}", share, "fraction")
            v = a.values[name][sel]
            lows, highs = a.intervals[name][0][sel], a.intervals[name][1][sel]
            known = np.isfinite(v)
            median = float(np.median(v[known])) if known.any() else np.nan
            raw = measured[f"{stem}_median_deg"]  # the frames' own angles: `raw_value`, what --norms compares
            if known.any() and np.isfinite(lows[known]).all():
                add(f"{stem}_median_deg", median, "deg", float(np.median(lows[known])), float(np.median(highs[known])),
                    INTERVAL_CLIP_MEDIAN, raw=raw)  # fmt: skip
            else:
                add(f"{stem}_median_deg", median, "deg", how="none: not every frame has a calibrated interval", raw=raw)
            add(f"{stem}_share_asymmetric", *_share(a, name, sel, frames, 1000 * p + SYMMETRY_NAMES.index(name)))
    return rows


def bootstrap_share(a: Analysis, name: str, sel: np.ndarray, frames: np.ndarray, seed: int) -> Share | None:
    """The block bootstrap of a person's (`sel (M,)`) share of frames asymmetric in `name`, over the frames with a
    calibrated value (None: no such frame)."""
    order = np.flatnonzero(sel)[np.argsort(frames[sel], kind="stable")]
    p = a.probabilities[name][order]
    known = p[np.isfinite(p)]
    if not len(known):
        return None
    return share_interval(known, block_frames(known, float(a.fps or 0.0)), a.settings.level, seed=seed)


def _share(a: Analysis, name: str, sel: np.ndarray, frames: np.ndarray, seed: int
           ) -> tuple[float, str, float, float, str]:  # fmt: skip
    """The clip row of a person's share of frames asymmetric in `name`: value, unit, interval, how
    (`share_calibration.calibrated_share`)."""
    counted = int(np.isfinite(a.probabilities[name][sel]).sum())
    value, low, high, how = calibrated_share(bootstrap_share(a, name, sel, frames, seed), name.removesuffix("_deg"),
                                             a.settings, counted, int(sel.sum()))  # fmt: skip
    return value, "fraction", low, high, how


def summary(a: Analysis) -> dict[str, dict[str, float | int]]:
    """Per frame measure: count, mean, median, min, max; for symmetry also the calls and bands."""
    out: dict[str, dict[str, float | int]] = {}
    for name in (*SYMMETRY_NAMES, *ANGLE_NAMES):
        v = a.values[name][np.isfinite(a.values[name])]
        stats: dict[str, float | int] = {"count": int(len(v))}
        if len(v):
            stats.update(mean=float(v.mean()), median=float(np.median(v)), min=float(v.min()), max=float(v.max()))
        if name in SYMMETRY_NAMES:
            stats.update({c: int((a.calls[name] == c).sum()) for c in CALLS})
            bands = symmetry_bands(v)
            stats.update({f"band_{b}": int((bands == b).sum()) for b in (1, 2, 3)})
        elif name in a.too_fast:
            stats["too_fast"] = int(a.too_fast[name].sum())
        out[name] = stats
    if a.head is not None:  # the head: tilt statistics and the turn calls counted
        tilt = a.head.tilt_deg[np.isfinite(a.head.tilt_deg)]
        out[TILT] = {"count": int(len(tilt))}
        if len(tilt):
            out[TILT].update(mean=float(tilt.mean()), median=float(np.median(tilt)), min=float(tilt.min()),
                             max=float(tilt.max()))  # fmt: skip
        calls = a.head.turn_call.astype(str)
        out[TURN] = {"count": int((calls != "").sum()), **{c: int((calls == c).sum()) for c in TURN_CALLS}}
    return out


def poses_counted(frames: np.ndarray, persons: np.ndarray) -> str:
    """Honest counts of analysed poses: "1 pose", "809 poses (809 frames, 1 person)", "12 poses
    (6 frames, 2 people)" (persons are tracks: places in their frame)."""
    n, f, p = len(frames), len(set(frames.tolist())), len(set(persons.tolist()))
    if n == 1:
        return "1 pose"
    return f"{plural(n, 'pose')} ({plural(f, 'frame')}, {plural(p, 'person', 'people')})"
