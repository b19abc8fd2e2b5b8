"""The head in the image: tilt and turn per frame from the input's face points and shoulders, and
head-turn shares and the median tilt per clip (docs/clinical.md, "Head").

Inputs are 2D, in the original image's pixels as the detector gave them: the face points that
`zedo lift` keeps beside the lifted joints (`ResultPoses.other_keypoints_2d`: nose, eyes, ears)
and the shoulders' input pixels (`ResultPoses.keypoints_2d`). Sides are the infant's own, taken
from the body's labelled left and right shoulders, never from the image: the measures are the
same whichever way the infant lies in the picture.

- `head_tilt_deg`: the signed angle between the eye line (right eye -> left eye) and the shoulder
  line (right shoulder -> left shoulder) in the image, the "habitual head deviation" of Wan et al.
  (FG 2023 workshops); 0 when parallel, positive when the head tilts towards the infant's own left
  shoulder (its left eye nearer the shoulder line than its right), in (-90, 90]. Which side of the
  shoulder line is headward comes from the eyes' midpoint, so a mirrored view (back to the
  camera) keeps the sign. An eye line pointing against the shoulder line (more than 90 degrees
  apart: eyes swapped by the detector?) is folded into (-90, 90] and flagged `eye_line_reversed`.
- `head_turn`: the yaw of the face, positive towards the infant's own left, estimated from where
  an anterior point sits between a lateral pair, along the pair's line oriented by the body's
  left-right axis: the nose between the ears, the nose between the eyes, the eyes' midpoint
  between the ears (without a nose). In an orthographic view the offset over half the pair's span
  is c tan(yaw), c the anterior point's depth in front of the pair over half its span
  (`HeadModel`, an infant's proportions); each available pair gives a yaw, weighted by its
  sensitivity (c times half its span in pixels, squared). The call: `midline` within
  `midline_deg` of facing the camera, else `left` or `right`. Turned far, the face shows one side
  only: with no complete pair, a hidden eye (else a hidden ear) beside a visible one and the nose
  on the hidden side of the visible one calls that side (the face turned towards it, into the
  mattress), without a value.

A frame without the points a measure needs gets an empty value and the reason (`how`), e.g.
``none: missing: left_eye``; a result without face points says so once.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from ...errors import ConfigError
from ...formats.readers.result import ResultPoses
from ..uncertainty.block_bootstrap import BootstrapSettings, ClipInterval, median_interval, share_intervals
from ..uncertainty.head_calibration import (
    HeadCalibration,
    bundled_head_calibrations,
    find_head_calibration,
    head_settings_key,
    widen,
)

FACE_JOINTS = ("nose", "left_eye", "right_eye", "left_ear", "right_ear")
SHOULDERS = ("left_shoulder", "right_shoulder")
TURN_CALLS = ("left", "right", "midline")
TILT = "head_tilt_deg"
TURN = "head_turn"
FLAG_EYES_REVERSED = "eye_line_reversed"
BASES = ("nose between the ears", "nose between the eyes", "eyes between the ears")  # head_turn's pairs
_NOSE, _LEYE, _REYE, _LEAR, _REAR = range(5)
NO_FACE_RESULT = (
    "the result does not carry the input's face points (written before zedo kept them): lift it again for the head"
)


@dataclass(frozen=True)
class HeadModel:
    """Proportions of an infant's head (0-3 months), for turning an offset into a yaw: the depth
    of an anterior point in front of a lateral pair over half the pair's span. Approximate: an
    interpupillary distance of about 3.9 cm, a bitragion breadth of about 9.5 cm, the nose tip about
    1.3 cm in front of the eyes and 6.5 cm in front of the ears; the calls hold within +-15 % of
    these (the benchmark varies every head's shape by that much)."""

    nose_over_eyes: float = 0.67  # 1.3 / (3.9 / 2)
    nose_over_ears: float = 1.37  # 6.5 / (9.5 / 2)
    eyes_over_ears: float = 1.09  # 5.2 / (9.5 / 2)


@dataclass(frozen=True)
class HeadSettings:
    """How the head measures are taken."""

    midline_deg: float = 20.0  # |turn| within this is midline
    min_confidence: float = 0.0  # face points below this confidence are missing (as lift's --min-confidence)
    model: HeadModel = field(default_factory=HeadModel)
    bootstrap: BootstrapSettings = field(default_factory=BootstrapSettings)

    def __post_init__(self) -> None:
        if not 0.0 < self.midline_deg < 90.0:
            raise ConfigError(f"head: midline_deg must be in (0, 90), got {self.midline_deg}")


@dataclass
class HeadFrames:
    """The head measures of N frames (analysed poses)."""

    tilt_deg: np.ndarray  # (N,) NaN where none
    tilt_how: np.ndarray  # (N,) object: the `interval` column (how, or "none: why")
    tilt_flag: np.ndarray  # (N,) object: "" or FLAG_EYES_REVERSED
    turn_deg: np.ndarray  # (N,) NaN where none (also for one-sided calls)
    turn_call: np.ndarray  # (N,) object: "left", "right", "midline" or ""
    turn_how: np.ndarray  # (N,) object


def face_points(result: ResultPoses, index: np.ndarray, min_confidence: float = 0.0) -> tuple[np.ndarray, str | None]:
    """The face points `(M, 5, 2)` (FACE_JOINTS order, pixels; NaN where missing or below
    `min_confidence`, as the lifted joints) of rows `index` of `result`, and why none can be had
    (None: some can)."""
    m = len(index)
    face = np.full((m, len(FACE_JOINTS), 2), np.nan)
    if result.other_keypoints_2d is None:
        return face, NO_FACE_RESULT
    names = result.other_keypoint_names
    have = [j for j, name in enumerate(FACE_JOINTS) if name in names]
    if not have:
        return face, "the input has no face points (nose, eyes, ears)"
    cols = [names.index(FACE_JOINTS[j]) for j in have]
    xy = result.other_keypoints_2d[index][:, cols]  # (M, E', 2)
    if result.other_keypoint_confidence is not None:
        conf = result.other_keypoint_confidence[index][:, cols]
        sure = (conf > 0) & (conf >= min_confidence)
        xy = np.where(sure[..., None], xy, np.nan)
    face[:, have] = xy
    return face, None


def shoulder_points(result: ResultPoses, index: np.ndarray) -> np.ndarray:
    """The shoulders' input pixels `(M, 2, 2)` (left, right) of rows `index`; NaN where unknown."""
    if result.keypoints_2d is None:
        return np.full((len(index), 2, 2), np.nan)
    cols = [result.skeleton.index(j) for j in SHOULDERS]
    return result.keypoints_2d[index][:, cols]


def _missing(points: np.ndarray, names: tuple[str, ...]) -> np.ndarray:
    """Per frame, "none: missing: a, b" for the NaN points of `points (N, P, 2)` ("" when none is)."""
    gone = ~np.isfinite(points).all(-1)  # (N, P)
    out = np.full(len(points), "", dtype=object)
    for pattern in np.unique(gone[gone.any(1)], axis=0):  # one string per pattern, not per frame
        rows = (gone == pattern).all(1)
        out[rows] = "none: missing: " + ", ".join(n for n, g in zip(names, pattern, strict=True) if g)
    return out


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.einsum("...i,...i->...", a, b)


def _unit(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    norm = np.linalg.norm(v, axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return v / norm[..., None], norm


def body_axis(shoulders: np.ndarray, face: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The body's left-right axis in the image (unit, right shoulder -> left shoulder) `(N, 2)`,
    and whether it can be used `(N,)`: both shoulders known, apart, and the shoulder line no
    shorter than the eye line where the eyes are known (else the infant lies on its side and the
    line says little about its own left and right)."""
    s = shoulders[:, 0] - shoulders[:, 1]  # (N, 2)
    x_hat, span = _unit(s)
    eye_span = np.linalg.norm(face[:, _LEYE] - face[:, _REYE], axis=-1)
    ok = np.isfinite(span) & (span > 0) & ~(np.isfinite(eye_span) & (span < eye_span))
    return x_hat, ok


def head_tilt(face: np.ndarray, shoulders: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """`head_tilt_deg (N,)`, its `how (N,)` and flag `(N,)` from face points `(N, 5, 2)` and
    shoulders `(N, 2, 2)` (module docstring)."""
    n = len(face)
    x_hat, usable = body_axis(shoulders, face)
    e = face[:, _LEYE] - face[:, _REYE]  # (N, 2) right eye -> left eye
    perp = np.stack([-x_hat[:, 1], x_hat[:, 0]], axis=-1)  # (N, 2)
    side = _dot(0.5 * (face[:, _LEYE] + face[:, _REYE]) - shoulders.mean(axis=1), perp)
    y_hat = np.sign(side)[:, None] * perp  # headward, perpendicular to the shoulder line
    directed = np.degrees(np.arctan2(_dot(e, y_hat), _dot(e, x_hat)))  # (N,) the eye line from the shoulder line
    ok = usable & np.isfinite(directed) & (side != 0) & (np.linalg.norm(e, axis=-1) > 0)
    tilt = np.where(ok, 90.0 - np.mod(90.0 + directed, 180.0), np.nan)  # -directed, folded into (-90, 90]
    how = np.full(n, "none: not calibrated (a 2D measure of the input keypoints)", dtype=object)
    points = np.concatenate([face[:, [_LEYE, _REYE]], shoulders], axis=1)
    missing = _missing(points, ("left_eye", "right_eye", *SHOULDERS))
    how[~ok] = "none: shoulder line foreshortened (the infant on its side) or eyes on the shoulder line"
    how[missing != ""] = missing[missing != ""]
    flag = np.where(ok & (np.abs(directed) > 90.0), FLAG_EYES_REVERSED, "").astype(object)
    return tilt, how, flag


def _pair_yaw(anterior: np.ndarray, left: np.ndarray, right: np.ndarray, x_hat: np.ndarray,
              c: float) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """Yaw (degrees, positive to the own left) `(N,)` from an anterior point between a lateral pair
    (all `(N, 2)`), and its weight (sensitivity squared; 0 where the pair cannot be used)."""
    d = left - right
    u, span = _unit(d)
    u = u * np.sign(_dot(u, x_hat))[:, None]  # the pair's line, pointing to the body's own left
    with np.errstate(invalid="ignore", divide="ignore"):
        tau = _dot(anterior - 0.5 * (left + right), u) / (0.5 * span)
    yaw = np.degrees(np.arctan(tau / c))
    ok = np.isfinite(yaw) & (span > 0) & (_dot(d, x_hat) != 0)
    return np.where(ok, yaw, 0.0), np.where(ok, (c * 0.5 * span) ** 2, 0.0)


def head_turn(face: np.ndarray, shoulders: np.ndarray, settings: HeadSettings | None = None
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:  # fmt: skip
    """`head_turn` per frame: yaw (N,) degrees (NaN where none), call (N,) and how (N,) from face
    points `(N, 5, 2)` and shoulders `(N, 2, 2)` (module docstring)."""
    settings = settings or HeadSettings()
    model = settings.model
    n = len(face)
    x_hat, usable = body_axis(shoulders, face)
    known = np.isfinite(face).all(-1)  # (N, 5)
    nose, leye, reye, lear, rear = (face[:, j] for j in range(5))
    eye_mid = 0.5 * (leye + reye)
    bases = [  # BASES' order: (anterior point, left, right, c)
        (nose, lear, rear, model.nose_over_ears),
        (nose, leye, reye, model.nose_over_eyes),
        (eye_mid, lear, rear, model.eyes_over_ears),
    ]
    y, w = (np.stack(v, axis=1) for v in zip(*(_pair_yaw(a, lt, rt, x_hat, c) for a, lt, rt, c in bases), strict=True))
    w[:, 2] = np.where(w[:, :2].sum(1) == 0, w[:, 2], 0.0)  # the eyes between the ears only without the nose
    total = w.sum(1)  # (N,)
    with np.errstate(invalid="ignore", divide="ignore"):
        yaw = np.where(usable & (total > 0), (y * w).sum(1) / total, np.nan)
    call = np.full(n, "", dtype=object)
    call[np.abs(yaw) <= settings.midline_deg] = "midline"
    call[yaw > settings.midline_deg] = "left"
    call[yaw < -settings.midline_deg] = "right"
    how = np.full(n, "", dtype=object)
    names = np.array(BASES, dtype=object)
    used = w > 0  # (N, 3)
    for pattern in np.unique(used[np.isfinite(yaw)], axis=0):
        rows = np.isfinite(yaw) & (used == pattern).all(1)
        how[rows] = "none: not calibrated (yaw from the " + " and the ".join(names[pattern]) + ", infant head model)"
    # One side of the face only: the call towards the hidden side, without a value.
    one_sided = usable & np.isnan(yaw) & known[:, _NOSE]
    eye_side = _hidden_side(known[:, _LEYE], known[:, _REYE])  # (N,) "left", "right" or ""
    ear_side = _hidden_side(known[:, _LEAR], known[:, _REAR])
    by_eye = eye_side != ""
    side = np.where(by_eye, eye_side, ear_side)
    seen = np.where(by_eye[:, None], np.where(known[:, [_LEYE]], leye, reye), np.where(known[:, [_LEAR]], lear, rear))
    toward = _dot(nose - seen, x_hat)  # > 0: the nose on the visible point's own-left side
    nose_agrees = np.where(side == "left", toward > 0, toward < 0)
    pairs_agree = ~by_eye | (ear_side == "") | (ear_side == eye_side)
    ok = one_sided & (side != "") & nose_agrees & pairs_agree
    call[ok] = side[ok]
    for s in ("left", "right"):
        for part, rows in (("eye", by_eye), ("ear", ~by_eye)):
            how[ok & rows & (side == s)] = f"none: one side of the face only ({s} {part} hidden): a call, no value"
    how[one_sided & (side != "") & ~ok] = "none: the visible face points contradict each other"
    rest = how == ""
    how[rest & ~usable] = "none: shoulder line foreshortened (the infant on its side) or missing"
    face_gone = ~known[:, [_NOSE, _LEYE, _REYE]].any(1)
    how[rest & usable & face_gone] = "none: face not visible (no nose, no eyes)"
    how[rest & usable & ~face_gone] = (
        "none: too few face points (the nose or the eyes' midpoint, and a pair of eyes or ears)"
    )
    missing = _missing(shoulders, SHOULDERS)
    how[rest & (missing != "")] = missing[rest & (missing != "")]
    return yaw, call, how


def _hidden_side(left_known: np.ndarray, right_known: np.ndarray) -> np.ndarray:
    """Per frame, the side of a pair that is hidden while the other shows: "left", "right" or ""."""
    return np.select([left_known & ~right_known, right_known & ~left_known], ["right", "left"], "").astype(object)


def head_frames(face: np.ndarray, shoulders: np.ndarray, settings: HeadSettings | None = None,
                why_none: str | None = None) -> HeadFrames:  # fmt: skip
    """Both head measures of N frames; `why_none` (a result without face points) empties them all."""
    tilt, tilt_how, tilt_flag = head_tilt(face, shoulders)
    yaw, call, turn_how = head_turn(face, shoulders, settings)
    if why_none is not None:
        n = len(face)
        empty = np.full(n, f"none: {why_none}", dtype=object)
        return HeadFrames(np.full(n, np.nan), empty, np.full(n, "", dtype=object), np.full(n, np.nan),
                          np.full(n, "", dtype=object), empty.copy())  # fmt: skip
    return HeadFrames(tilt, tilt_how, tilt_flag, yaw, call, turn_how)


@dataclass(frozen=True)
class ClipStat:
    """One per-clip head row: measure, value, unit and interval."""

    measure: str
    value: float
    unit: str
    interval: ClipInterval


def head_clip(frames: np.ndarray, head: HeadFrames, fps: float, settings: HeadSettings | None = None,
              why_none: str | None = None, calibrations: Sequence[HeadCalibration] | None = None,
              level: float | None = None) -> list[ClipStat]:  # fmt: skip
    """A person track's clip rows: `head_turn_fraction_<call>` (the share of its frames with a call;
    exactly the frame rows' calls, counted) and `head_tilt_median_deg`, each with its calibrated
    interval at `level` (default: the bootstrap's, 0.9): the block bootstrap's
    (`head_clip_bootstrap`) widened by the factor of the calibration fitted with these settings
    (`head_calibration`; `calibrations`, by default the bundled ones). Without one, no interval:
    the bootstrap alone under-covers."""
    settings = settings or HeadSettings()
    level = settings.bootstrap.level if level is None else level
    stats = head_clip_bootstrap(frames, head, fps, settings, why_none)
    calibrations = bundled_head_calibrations() if calibrations is None else calibrations
    key = head_settings_key(settings.midline_deg, settings.model, settings.bootstrap)
    cal = find_head_calibration(calibrations, key)
    out = []
    for s in stats:
        measure = cal.measures[s.measure] if cal is not None else None
        if not np.isfinite(s.interval.low):
            out.append(s)
        elif measure is None or level not in measure.levels:
            why = (f"none: no calibration of the head intervals for these settings (midline_deg, head model, "
                   f"bootstrap) at {level:.0%}; the block bootstrap alone under-covers")  # fmt: skip
            out.append(ClipStat(s.measure, s.value, s.unit, ClipInterval(np.nan, np.nan, 0, why)))
        else:
            out.append(ClipStat(s.measure, s.value, s.unit, widen(s.measure, s.value, s.interval, measure, level)))
    return out


def head_clip_bootstrap(frames: np.ndarray, head: HeadFrames, fps: float, settings: HeadSettings | None = None,
                        why_none: str | None = None) -> list[ClipStat]:  # fmt: skip
    """`head_clip`'s rows with the block bootstrap's intervals as they come, before calibration
    (what the calibration is fitted on). `frames (T,)` are the track's frame numbers, `head` its
    frames' measures."""
    settings = settings or HeadSettings()
    grid = frames - frames.min()  # (T,) places on the clip's frame grid
    length = int(grid.max()) + 1
    calls = head.turn_call.astype(str)
    called = calls != ""
    stats: list[ClipStat] = []
    if why_none is not None or not called.any():
        why = f"none: {why_none}" if why_none is not None else "none: no frame with a head_turn call"
        none = ClipInterval(np.nan, np.nan, 0, why)
        stats += [ClipStat(f"head_turn_fraction_{c}", np.nan, "fraction", none) for c in TURN_CALLS]
    else:
        ind = np.full((len(TURN_CALLS), length), np.nan)  # (C, L) on the frame grid
        for c, name in enumerate(TURN_CALLS):
            ind[c, grid[called]] = calls[called] == name
        shares = [float((calls[called] == name).sum() / called.sum()) for name in TURN_CALLS]
        intervals = share_intervals(ind, fps, settings.bootstrap)
        stats += [ClipStat(f"head_turn_fraction_{c}", s, "fraction", i)
                  for c, s, i in zip(TURN_CALLS, shares, intervals, strict=True)]  # fmt: skip
    known = np.isfinite(head.tilt_deg)
    if why_none is not None or not known.any():
        why = f"none: {why_none}" if why_none is not None else "none: no frame with a head_tilt_deg value"
        stats.append(ClipStat("head_tilt_median_deg", np.nan, "deg", ClipInterval(np.nan, np.nan, 0, why)))
    else:
        series = np.full(length, np.nan)
        series[grid[known]] = head.tilt_deg[known]
        interval = median_interval(series, fps, settings.bootstrap)
        stats.append(ClipStat("head_tilt_median_deg", float(np.median(head.tilt_deg[known])), "deg", interval))
    return stats
