"""Per person track of a clip: the published 2D features (`published_features`) from the input's 2D
keypoints, and the `3d_` features (`features_3d`) from the lifted poses, as named values with the
`interval` column's text (docs/movement.md).

A track's frames are its rows' `frame_index`; a frame without the person is a gap (interpolated, as a
missed detection is). The frames run from the track's first to its last: the published pipeline starts at
frame 0, which changes no feature (the frames before a track's first are unknown, and the statistics skip
unknown frames).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from ..formats.result_reader import ResultPoses
from .features_3d import features_3d
from .published_features import ClipFeatures, published_features

INTERVAL_PUBLISHED = "none: published 2D feature"
INTERVAL_3D = "none: 3d_ features are not calibrated yet"


@dataclass(frozen=True)
class ClipFeature:
    """One clip feature of one person: a row of the tidy table without frame columns."""

    person: int
    measure: str
    value: float
    unit: str
    interval: str  # why the row has no 90 % interval, or why its value is empty


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


def clip_features(result: ResultPoses, index: np.ndarray, fps: float) -> list[ClipFeature]:
    """The published 2D and the `3d_` features of every person track among the analysed rows `index`."""
    out: list[ClipFeature] = []
    skel = result.skeleton
    for p in sorted(set(result.person[index].tolist())):
        rows = np.flatnonzero(result.person == p)  # every row of the track: its 2D whether lifted or not
        lifted = index[result.person[index] == p]
        frames = result.frame_index[rows]
        first, length = int(frames.min()), int(frames.max() - frames.min()) + 1
        if result.keypoints_2d is None:
            blank = published_features(np.full((1, skel.num_joints, 2), np.nan), skel, fps, np.ones(2))
            why = "none: the result file carries no 2D keypoints"
            out += [ClipFeature(p, name, np.nan, blank.units[name], why) for name in blank.values]
        else:
            xy = _track(frames, result.keypoints_2d[rows], first, length)  # (T, J, 2)
            sizes = _track(frames, _image_sizes(result, rows), first, length)  # (T, 2)
            sizes = np.where(np.isfinite(sizes), sizes, np.nanmedian(sizes, axis=0))  # frames without the person
            out += _rows(p, published_features(xy, skel, fps, sizes), INTERVAL_PUBLISHED)
        poses = _track(result.frame_index[lifted], result.poses[lifted], first, length)  # (T, J, 3)
        out += _rows(p, features_3d(poses, skel, fps), INTERVAL_3D)
    return out
