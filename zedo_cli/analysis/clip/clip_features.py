"""Per person track of a clip: the published 2D features (`published_features`) from the input's 2D
keypoints, and the `3d_` features (`features_3d`) from the lifted poses, as named values with the
`interval` column's text (docs/movement.md).

The `3d_` features take a shrinkage estimate and a 90 % interval from a clip-scope measure calibration
(`calibration.MeasureCalibration`, scope "clips", fitted on held-out clips by benchmarks/
features_3d_accuracy.py) where one holds for the result; the raw feature goes in `raw_value`, and where
none holds the reason goes in `interval`.

A track's frames are its rows' `frame_index`; a frame without the person is a gap (interpolated, as a
missed detection is). The frames run from the track's first to its last: the published pipeline starts at
frame 0, which changes no feature (the frames before a track's first are unknown, and the statistics skip
unknown frames).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, replace

import numpy as np

from ...formats.readers.result import ResultPoses
from ...stats import TOO_FEW_CASES
from ..uncertainty.calibration import DEFAULT_LEVEL, MeasureCalibration, clip_camera_mismatch
from .features_3d import PREFIX, features_3d
from .published_features import ClipFeatures, published_features

INTERVAL_PUBLISHED = "none: published 2D feature"
INTERVAL_CALIBRATED = "calibrated"
# the mean angle's range per part (the angle conventions of features_3d)
_MEAN_ANGLE = {"Elbow": (0.0, 180.0), "Knee": (0.0, 180.0), "HipAbduction": (-90.0, 90.0),
               "ShoulderAbduction": (-90.0, 90.0), "HipFlexion": (-90.0, 270.0),
               "ShoulderFlexion": (-90.0, 270.0)}  # fmt: skip
_NON_NEGATIVE = ("stdev_angle", "median_vel_angle", "IQR_vel_angle", "IQR_acc_angle", "mean_dispersion")


def feature_range(name: str) -> tuple[float, float]:
    """The values a `3d_` feature (e.g. `3d_mean_angle_LKnee`) can take: estimates and intervals stay in them."""
    stem = name.removeprefix(PREFIX)
    if stem.startswith("lrCorr_"):
        return -1.0, 1.0
    if stem.startswith("mean_angle_"):
        return _MEAN_ANGLE.get(stem.removeprefix("mean_angle_")[1:], (-np.inf, np.inf))  # the part, past L / R
    if stem.startswith(_NON_NEGATIVE):
        return 0.0, np.inf
    return -np.inf, np.inf


@dataclass(frozen=True)
class ClipFeature:
    """One clip feature of one person: a row of the tidy table without frame columns."""

    person: int
    measure: str
    value: float
    unit: str
    interval: str  # "calibrated", why the row has no 90 % interval, or why its value is empty
    raw_value: float = np.nan  # a calibrated feature's measured value (`value`: the shrinkage estimate)
    low: float = np.nan  # the calibrated interval's ends
    high: float = np.nan


def _track(frames: np.ndarray, values: np.ndarray, first: int, length: int) -> np.ndarray:
    """`values (n, ...)` at `frames (n,)` placed on a track of `length` frames from `first`, NaN elsewhere."""
    out = np.full((length, *values.shape[1:]), np.nan)
    out[frames - first] = values
    return out


def _image_sizes(result: ResultPoses, rows: np.ndarray) -> np.ndarray:
    """`(n, 2)` width, height of each row's frame; where unknown, the track's first known one, else
    (0, 1): the features do not depend on it (the body frame and the angles are free of translation
    and scale), it only centres the coordinates as the published code does."""
    sizes = np.full((len(rows), 2), np.nan)
    if result.cameras is not None:
        for k, i in enumerate(rows):
            cam = result.cameras[i]
            if cam is not None and cam.image_size is not None:
                sizes[k] = cam.image_size
    known = np.isfinite(sizes).all(1)
    sizes[~known] = sizes[known][0] if known.any() else (0.0, 1.0)
    return sizes


def _rows(person: int, features: ClipFeatures, interval: str) -> Iterator[ClipFeature]:
    for name, value in features.values.items():
        how = interval if np.isfinite(value) else f"none: {features.reasons[name]}"
        yield ClipFeature(person, name, value, features.units[name], how)


def _calibrated(
    person: int, features: ClipFeatures, calibration: MeasureCalibration | None, why_not: str, level: float
) -> Iterator[ClipFeature]:
    """The `3d_` rows of one track: estimate and interval at `level` where `calibration` has the feature's model."""
    for f in _rows(person, features, f"none: {why_not}"):
        model = None if calibration is None else calibration.measures.get(f.measure)
        if not np.isfinite(f.value) or calibration is None:
            yield f
        elif model is None:
            yield replace(f, interval=f"none: the measure calibration has no {f.measure}")
        else:
            lo_r, hi_r = feature_range(f.measure)
            est = model.estimate(np.array([f.value]))  # (1,)
            low, high = (float(np.clip(x[0], lo_r, hi_r)) for x in model.interval(est, np.array([f.value]), level))
            if np.isnan(low) or np.isnan(high):
                yield replace(f, interval=f"none: {TOO_FEW_CASES}")
                continue
            yield replace(f, value=float(np.clip(est[0], lo_r, hi_r)), raw_value=f.value, low=low, high=high,
                          interval=INTERVAL_CALIBRATED)  # fmt: skip


@dataclass(frozen=True)
class TrackArrays:
    """One person track on its own frame grid, from its first frame to its last (NaN where a frame lacks it)."""

    first: int  # the track's first frame
    xy: np.ndarray | None  # (T, J, 2) the input's 2D; None: the result carries no 2D
    sizes: np.ndarray  # (T, 2) each frame's image width and height
    poses: np.ndarray  # (T, J, 3) the lifted poses of the analysed rows


def track_arrays(result: ResultPoses, index: np.ndarray, person: int) -> TrackArrays:
    """Person `person`'s track among the analysed rows `index`: its 2D (every row, lifted or not) and lifted poses."""
    rows = np.flatnonzero(result.person == person)
    lifted = index[result.person[index] == person]
    frames = result.frame_index[rows]
    first, length = int(frames.min()), int(frames.max() - frames.min()) + 1
    sizes = _track(frames, _image_sizes(result, rows), first, length)  # (T, 2)
    sizes = np.where(np.isfinite(sizes), sizes, np.nanmedian(sizes, axis=0))  # frames without the person
    xy = None if result.keypoints_2d is None else _track(frames, result.keypoints_2d[rows], first, length)
    return TrackArrays(first, xy, sizes, _track(result.frame_index[lifted], result.poses[lifted], first, length))


def epoch_features(result: ResultPoses, index: np.ndarray, fps: float, person: int, epoch_frames: int
                   ) -> list[dict[str, float]]:  # fmt: skip
    """The measured published 2D and `3d_` features of each whole epoch of `epoch_frames` frames of a person's
    track, in order (a remainder shorter than an epoch is left out)."""
    track = track_arrays(result, index, person)
    out = []
    for start in range(0, len(track.poses) - epoch_frames + 1, epoch_frames):
        span = slice(start, start + epoch_frames)
        values = dict(features_3d(track.poses[span], result.skeleton, fps).values)
        if track.xy is not None:
            values.update(published_features(track.xy[span], result.skeleton, fps, track.sizes[span]).values)
        out.append(values)
    return out


def clip_features(
    result: ResultPoses, index: np.ndarray, fps: float, calibration: MeasureCalibration | None = None,
    why_not: str = "no measure calibration installed", level: float = DEFAULT_LEVEL,
    cameras: tuple[np.ndarray, np.ndarray] | None = None, outside: np.ndarray | None = None,
    stand_in: MeasureCalibration | None = None,
) -> list[ClipFeature]:  # fmt: skip
    """The published 2D and the `3d_` features of every person track among the analysed rows `index`; the
    `3d_` ones calibrated under `calibration` (a clip-scope one, `find_calibration(..., scope="clips")`),
    None: uncalibrated, with `why_not` in their `interval`. `cameras`: the root depth and focal length `(M,)`
    of each row of `index` (`analyse.pose_cameras`), for a calibration over known cameras, which holds track
    by track (`clip_camera_mismatch`); without them such a calibration cannot be checked and is not used.
    `outside (M,)`: per row of `index` why its track lies outside the calibration clips ("" where not).
    `stand_in`: the pseudo camera's clip calibration, for a track whose stated camera lies outside `calibration`'s
    range (`calibration.camera_stand_in`)."""
    out: list[ClipFeature] = []
    skel = result.skeleton
    for p in sorted(set(result.person[index].tolist())):
        mine = result.person[index] == p  # (M,): the track's analysed rows
        track = track_arrays(result, index, p)
        if track.xy is None:
            blank = published_features(np.full((1, skel.num_joints, 2), np.nan), skel, fps, np.ones(2))
            why = "none: the result file carries no 2D keypoints"
            out += [ClipFeature(p, name, np.nan, blank.units[name], why) for name in blank.values]
        else:
            out += _rows(p, published_features(track.xy, skel, fps, track.sizes), INTERVAL_PUBLISHED)
        poses = track.poses
        track_calibration, track_why = calibration, why_not
        if calibration is not None and calibration.domain is not None:
            depth, focal = cameras if cameras is not None else (np.full(len(index), np.nan),) * 2
            why = clip_camera_mismatch(calibration, depth[mine], focal[mine])
            if why is not None:
                track_calibration, track_why = stand_in, why
        if outside is not None and outside[mine].any() and outside[mine][0]:  # unlike the calibration clips
            track_calibration, track_why = None, str(outside[mine][0])
        out += _calibrated(p, features_3d(poses, skel, fps), track_calibration, track_why, level)
    return out
