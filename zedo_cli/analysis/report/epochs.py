"""A long track drawn by epochs: its frames cut into consecutive epochs, and per epoch the quartiles of a series or
the mean of a flag or count, so that a 10-minute clip's plot shows its course instead of 18,000 frames in a
panel's 500 px. Vectorised: each epoch's frames are a row of one NaN-padded matrix."""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from ..analyse import Analysis

SUMMARY_OVER_S = 120.0  # a track lasting longer than this is drawn by epochs, not frame by frame
SUMMARY_EPOCH_S = 10.0  # the shortest epoch, lengthened in steps of itself to keep at most SUMMARY_EPOCHS
SUMMARY_EPOCHS = 60


@dataclass(frozen=True)
class Epochs:
    """One person's frames cut into consecutive epochs of `seconds`: the positions in `a.index` of the track's
    frames in time order `pos (T,)`, each one's epoch `(T,)`, and the epochs' mid times `t (E,)` in seconds."""

    pos: np.ndarray
    epoch: np.ndarray
    t: np.ndarray
    seconds: float

    def matrix(self, values: np.ndarray) -> np.ndarray:
        """`values` over `a.index` `(M,)` as `(E, L)`: each epoch's frames in a row, NaN-padded (an epoch
        without frames, a gap in the track, is a row of NaN)."""
        start = np.searchsorted(self.epoch, np.arange(len(self.t)))  # (E,) first frame of each epoch
        rank = np.arange(len(self.epoch)) - start[self.epoch]  # (T,) place within its epoch
        out = np.full((len(self.t), int(rank.max()) + 1), np.nan)
        out[self.epoch, rank] = np.asarray(values, float)[self.pos]
        return out

    def quartiles(self, values: np.ndarray) -> np.ndarray:
        """`(3, E)`: each epoch's 25th, 50th and 75th percentile of `values (M,)` (NaN where it has none)."""
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # an epoch without a value: NaN, as meant
            return np.nanpercentile(self.matrix(values), [25, 50, 75], axis=1)

    def mean(self, values: np.ndarray) -> np.ndarray:
        """`(E,)`: each epoch's mean of `values (M,)`, of a flag its share of frames (NaN for an epoch without
        frames)."""
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            return np.nanmean(self.matrix(np.asarray(values, float)), axis=1)


def epochs_of(a: Analysis, person: int) -> Epochs | None:
    """Person `person`'s track by epochs where it lasts over SUMMARY_OVER_S (None: short enough to draw frame by
    frame, or no fps)."""
    if not a.fps:
        return None
    res = a.result
    pos = np.flatnonzero(res.person[a.index] == person)
    pos = pos[np.argsort(res.frame_index[a.index][pos], kind="stable")]
    t = res.frame_index[a.index][pos] / float(a.fps)
    if not len(t) or t[-1] - t[0] <= SUMMARY_OVER_S:
        return None
    span = t[-1] - t[0]
    seconds = SUMMARY_EPOCH_S * math.ceil(span / SUMMARY_EPOCHS / SUMMARY_EPOCH_S)
    epoch = np.minimum(((t - t[0]) // seconds).astype(int), int(span // seconds))
    count = int(epoch.max()) + 1
    return Epochs(pos, epoch, t[0] + seconds * (np.arange(count) + 0.5), float(seconds))
