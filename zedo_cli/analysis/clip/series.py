"""Time-series steps and clip statistics shared by the clip features (`published_features`,
`features_3d`), with the semantics of the pandas 1.x calls of Chambers et al. 2020's published code,
written out in numpy (pandas is not a dependency). Every function works along axis 0 (frames) of
arrays `(T, ...)`, on all columns at once.

- `interpolate_gaps`: pandas `Series.interpolate()` (linear in the position): interior gaps filled
  linearly, leading NaNs left NaN, trailing NaNs filled with the last known value.
- `rolling_centered`: pandas `rolling(window=w, center=True).median()` / `.mean()`: frame i uses frames
  i - w//2 .. i - w//2 + w - 1 (for an even w one more frame before i than after), and is NaN unless all
  w frames exist and are known (pandas' default min_periods = w).
- `rolling_trailing_mean`: `rolling(window=w).mean()`: frames i - w + 1 .. i, NaN unless all known.
- `step_difference`: the published `get_delta`: 0 at the first frame (NaN when it is unknown), then the
  difference from the previous row, NaN wherever the row is unknown.
- Statistics that skip NaNs as pandas does: `iqr` (quantiles with linear interpolation), `circular_mean_deg`
  and `circular_variance` (circstats.py: the mean resultant vector), `entropy_of_rounded` (natural log of
  the frequencies of the rounded values, scipy.stats.entropy); Pearson's r (pairwise complete) is `stats.pearson`.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view


def interpolate_gaps(x: np.ndarray) -> np.ndarray:
    """`x (T, ...)` with interior NaN runs filled linearly by position, trailing NaNs filled with the
    last known value and leading NaNs kept (pandas `interpolate()`, method linear, forward)."""
    t = len(x)
    flat = x.reshape(t, -1)  # (T, C)
    known = np.isfinite(flat)
    pos = np.arange(t)[:, None]
    prev = np.maximum.accumulate(np.where(known, pos, -1), axis=0)  # (T, C) last known row at or before
    nxt = np.minimum.accumulate(np.where(known, pos, t)[::-1], axis=0)[::-1]  # first known row at or after
    cols = np.arange(flat.shape[1])[None, :]
    p = np.clip(prev, 0, t - 1)
    n = np.clip(nxt, 0, t - 1)
    y0, y1 = flat[p, cols], flat[n, cols]
    with np.errstate(invalid="ignore", divide="ignore"):
        slope = (y1 - y0) / (n - p)
        inner = slope * (pos - p) + y0  # numpy's interp: slope * (x - x_j) + y_j
    out = np.where(known, flat, np.nan)
    gap = ~known & (prev >= 0)
    out = np.where(gap & (nxt < t), inner, out)
    out = np.where(gap & (nxt >= t), y0, out)  # trailing: the last known value
    return out.reshape(x.shape)


def _windows(x: np.ndarray, window: int) -> np.ndarray:
    """`(T - w + 1, C, w)` views of the frames of `x (T, C)`."""
    return sliding_window_view(x, window, axis=0)


def rolling_centered(x: np.ndarray, window: int, stat: Literal["median", "mean"]) -> np.ndarray:
    """The centred rolling median or mean of `x (T, ...)` over `window` frames (pandas center=True)."""
    t = len(x)
    flat = x.reshape(t, -1)
    out = np.full(flat.shape, np.nan)
    if window <= 0:
        return out.reshape(x.shape)
    if t >= window:
        w = _windows(flat, window)  # (T - w + 1, C, w)
        start = window // 2  # the row of the first full window: pandas' offset (w - 1) // 2 after its end
        out[start : start + t - window + 1] = _median(flat, w) if stat == "median" else w.mean(axis=-1)
    return out.reshape(x.shape)


_MEDIAN_ROWS = 2048


def _median(flat: np.ndarray, w: np.ndarray) -> np.ndarray:
    """The median of each window `w (T - n + 1, C, n)` of `flat (T, C)`, NaN where the window holds a NaN
    (the mean of the two middle values for an even n, as np.median and pandas take it)."""
    n = w.shape[-1]
    lo, hi = (n - 1) // 2, n // 2
    med = np.empty(w.shape[:-1])
    for start in range(0, len(w), _MEDIAN_ROWS):  # the windows copied a block of rows at a time
        part = np.partition(w[start : start + _MEDIAN_ROWS], [lo, hi] if lo != hi else lo, axis=-1)
        med[start : start + _MEDIAN_ROWS] = (part[..., lo] + part[..., hi]) / 2
    nans = np.concatenate([np.zeros((1, flat.shape[1])), np.cumsum(np.isnan(flat), axis=0)])  # (T + 1, C)
    return np.where(nans[n:] - nans[:-n] > 0, np.nan, med)


def rolling_trailing_mean(x: np.ndarray, window: int) -> np.ndarray:
    """The trailing rolling mean of `x (T, ...)`: frame i averages frames i - w + 1 .. i (pandas default)."""
    t = len(x)
    flat = x.reshape(t, -1)
    out = np.full(flat.shape, np.nan)
    if 0 < window <= t:
        out[window - 1 :] = _windows(flat, window).mean(axis=-1)
    return out.reshape(x.shape)


def step_difference(x: np.ndarray) -> np.ndarray:
    """The published `get_delta` of `x (T, ...)`: row 0 is 0 (NaN if unknown), row i is x_i - x_{i-1},
    NaN wherever x_i is unknown."""
    out = np.empty_like(x, dtype=float)
    if not len(x):
        return out
    out[0] = 0.0
    out[1:] = np.diff(x, axis=0)
    return out * (x * 0.0 + 1.0)


def shortest_turn_deg(prev: np.ndarray, cur: np.ndarray) -> np.ndarray:
    """The change from `prev` to `cur` (degrees) the shortest way round: of d, d + 360 and d - 360 the
    one of least magnitude, the first on a tie (so +-180 stays as it is)."""
    d = cur - prev
    options = np.stack([d, d + 360.0, d - 360.0])  # (3, ...)
    pick = np.argmin(np.abs(options), axis=0)
    return np.take_along_axis(options, pick[None], axis=0)[0]


def nan_median(x: np.ndarray) -> float:
    """The median of the known values of `x` (NaN if none)."""
    v = x[np.isfinite(x)]
    return float(np.median(v)) if len(v) else np.nan


def iqr(x: np.ndarray) -> float:
    """75th minus 25th percentile of the known values (linear interpolation, pandas `quantile`)."""
    v = x[np.isfinite(x)]
    if not len(v):
        return np.nan
    q25, q75 = np.quantile(v, [0.25, 0.75])
    return float(q75 - q25)


def _resultant(angles_rad: np.ndarray) -> tuple[complex, int]:
    z = np.exp(1j * angles_rad[np.isfinite(angles_rad)])
    return complex(z.sum()), len(z)


def circular_mean_deg(angles_deg: np.ndarray) -> float:
    """The direction of the mean resultant vector of the known angles, degrees in (-180, 180]."""
    r, n = _resultant(np.radians(angles_deg))
    return float(np.degrees(np.angle(r))) if n else np.nan


def circular_variance(angles_deg: np.ndarray) -> float:
    """1 - the mean resultant length of the known angles (dimensionless, 0 = all equal)."""
    r, n = _resultant(np.radians(angles_deg))
    return float(1.0 - abs(r) / n) if n else np.nan


def entropy_of_rounded(x: np.ndarray, decimals: int) -> float:
    """Shannon entropy (nats) of the frequencies of the known values rounded to `decimals` (numpy's
    round half to even, as pandas rounds). NaN when no value is known, where scipy.stats.entropy of the
    published code gives 0: no entropy can be measured from nothing."""
    v = np.round(x[np.isfinite(x)], decimals)
    if not len(v):
        return np.nan
    _, counts = np.unique(v, return_counts=True)
    p = counts / counts.sum()
    return float(-(p * np.log(p)).sum())
