"""A 2D detector's habits found in a track before it is lifted as one infant (`--temporal clip`).

- **Left and right exchanged** for a few frames: over the track, each frame is read as labelled or with its
  left and right joints exchanged, whichever keeps the pose closest to its neighbours (a Viterbi pass over the
  frames; reading a frame exchanged costs `SWAP_PRIOR` of the pose's size, so a frame the 2D cannot settle, a
  near-symmetric pose, stays as labelled). Frames read exchanged are corrected and flagged.
- **A joint jumping away** (to an adult's hand, say) for a few frames: a joint further than `OUTLIER_SIZE` times
  the pose's 2D size from its own running median over `OUTLIER_WINDOW_S`, much further than its parent joint is
  from its own, and that got there (or left) by one step of over `JUMP_STEP` times the pose's size, is not used
  as a constraint (the prior fills it) and is flagged.

Missing joints and frames without the person stay as they are: the lift treats them as gaps.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

from .clip import best_path

SWAP_PRIOR = 0.05  # of the pose's 2D size, per frame read exchanged
OUTLIER_SIZE = 0.35  # of the pose's 2D size: a joint further than this from its running median is an outlier
JUMP_STEP = 0.2  # of the pose's 2D size: a joint entering or leaving an outlying run by a step this long jumped
OUTLIER_OWN = 2.0  # a joint's own jump: over this many times its parent joint's distance from the parent's median
OUTLIER_WINDOW_S = 1.0  # seconds of the running median (longer than the jumps it must see through)


@dataclass(frozen=True)
class DetectionFixes:
    """What was found in a track's 2D: frames whose left and right were exchanged `(T,)` (corrected) and joints
    far off their own path `(T, J)` (not used)."""

    swapped: np.ndarray
    outliers: np.ndarray


def pose_size(xy: np.ndarray) -> np.ndarray:
    """The size of 2D poses `(..., J, 2)` in pixels `(...,)`: the RMS distance of the known joints from their mean
    (NaN for a pose without a known joint)."""
    known = np.isfinite(xy).all(-1)  # (..., J)
    count = known.sum(-1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        c = np.where(known[..., None], xy, 0.0).sum(-2, keepdims=True) / count[..., None]
        d2 = np.where(known, ((xy - c) ** 2).sum(-1), 0.0)
        return np.sqrt(d2.sum(-1) / count[..., 0])


def find_swaps(xy: np.ndarray, flip: list[int]) -> np.ndarray:
    """Frames `(T,)` of one track (in time order) read best with left and right exchanged (`flip`, the joint
    permutation that exchanges them)."""
    t = len(xy)
    if t < 2:
        return np.zeros(t, bool)
    size = np.nanmedian(pose_size(xy))
    views = (xy, xy[:, flip])
    # pair[i, a, b]: mean joint distance between frame i read a and frame i + 1 read b, in pose sizes
    pair = np.zeros((t - 1, 2, 2))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # a pair of frames without a joint in common: no step
        for a in (0, 1):
            for b in (0, 1):
                step = np.linalg.norm(views[b][1:] - views[a][:-1], axis=-1)
                pair[:, a, b] = np.nan_to_num(np.nanmean(step, axis=1) / size, nan=0.0)
    return best_path(np.tile([0.0, SWAP_PRIOR], (t, 1)), pair).astype(bool)


def find_outliers(xy: np.ndarray, fps: float, parents: list[int | None]) -> np.ndarray:
    """Joints `(T, J)` of one track further than OUTLIER_SIZE x the pose's size from their running median, and over
    OUTLIER_OWN times as far as their parent joint (`parents`, per joint; None: the pose's median joint) is from
    its own: a limb moving faster than the median follows leaves all its joints behind it, a jump one."""
    t = len(xy)
    half = max(1, int(round(OUTLIER_WINDOW_S * fps / 2)))
    if t < 2 * half + 1:
        return np.zeros(xy.shape[:2], bool)
    padded = np.pad(xy, ((half, half), (0, 0), (0, 0)), constant_values=np.nan)
    windows = sliding_window_view(padded, 2 * half + 1, axis=0)  # (T, J, 2, w)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # an all-NaN window: no median, no outlier
        median = np.nanmedian(windows, axis=-1)
        size = np.nanmedian(pose_size(xy))
    off = np.linalg.norm(xy - median, axis=-1)  # (T, J)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        typical = np.nanmedian(off, axis=1)
    parent_off = np.stack([typical if p is None else off[:, p] for p in parents], 1)
    far = (off > OUTLIER_SIZE * size) & ~(off <= OUTLIER_OWN * np.nan_to_num(parent_off, nan=0.0))
    return sudden(np.nan_to_num(far, nan=0.0).astype(bool), xy, JUMP_STEP * size)


def sudden(far: np.ndarray, xy: np.ndarray, step: float) -> np.ndarray:
    """The runs of `far (T, J)` frames that a joint entered or left by a jump of over `step` px from one frame to
    the next (a detection moving to another object jumps; a fast limb travels)."""
    out = np.zeros_like(far)
    for j in np.flatnonzero(far.any(0)):
        edges = np.diff(np.r_[0, far[:, j].astype(np.int8), 0])
        for start, stop in zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1), strict=True):
            steps = [np.linalg.norm(xy[start, j] - xy[start - 1, j]) if start > 0 else np.nan,
                     np.linalg.norm(xy[stop, j] - xy[stop - 1, j]) if stop < len(far) else np.nan]  # fmt: skip
            if np.nanmax(np.r_[steps, 0.0]) > step:
                out[start:stop, j] = True
    return out


def fix_detections(xy: np.ndarray, confidence: np.ndarray, flip: list[int], fps: float, tracks: list[np.ndarray],
                   parents: list[int | None]) -> tuple[np.ndarray, np.ndarray, DetectionFixes]:  # fmt: skip
    """The 2D `(N, J, 2)` and confidences `(N, J)` with exchanged frames corrected and outliers dropped (NaN,
    confidence 0), per track (`tracks`: each track's instance indices in time order), and what was found."""
    xy, confidence = xy.astype(np.float64, copy=True), confidence.astype(np.float64, copy=True)
    swapped = np.zeros(len(xy), bool)
    outliers = np.zeros(xy.shape[:2], bool)
    for idx in tracks:
        seen = np.where((confidence[idx] > 0)[..., None], xy[idx], np.nan)
        swaps = find_swaps(seen, flip)
        xy[idx[swaps]] = xy[idx[swaps]][:, flip]
        confidence[idx[swaps]] = confidence[idx[swaps]][:, flip]
        swapped[idx] = swaps
        seen = np.where((confidence[idx] > 0)[..., None], xy[idx], np.nan)
        outliers[idx] = find_outliers(seen, fps, parents)
    confidence[outliers] = 0.0
    xy[outliers] = np.nan
    return xy, confidence, DetectionFixes(swapped, outliers)
