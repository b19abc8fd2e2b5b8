"""Intervals for clip statistics of frame series whose neighbouring frames are correlated: the
circular block bootstrap (Politis & Romano 1992), percentile intervals.

A clip is one stretch of an infant's behaviour: a head held to one side for seconds gives
hundreds of frames that say the same thing, so a binomial interval over frames taken as
independent is far too narrow. The bootstrap resamples whole blocks of consecutive frames; the
block length is chosen from the series' own autocorrelation (Politis & White 2004, with the
correction of Patton, Politis & White 2009: the circular bootstrap's optimal block), and never
shorter than `min_block_s` seconds of frames (so it is tied to the fps). The interval is for the
long-run share (or median) of the process the clip was drawn from; its coverage on synthetic
clips is measured by `benchmarks/head_measures.py` (docs/clinical.md, "Head").

Series lie on the clip's frame grid (`frame - first frame`), NaN where a frame has no value (not in
the result, or no call): a replicate's share is the ratio of its blocks' counts, so gaps keep their
place in time. Vectorised: a replicate is a row of block starts, a block's count a difference of
cumulative sums (shares); medians gather the replicate's frames in chunks of replicates.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ConfigError


@dataclass(frozen=True)
class BootstrapSettings:
    """The block bootstrap's settings (recorded with every interval it gives)."""

    replicates: int = 1000
    level: float = 0.9
    min_block_s: float = 1.0  # blocks hold at least this many seconds of frames
    seed: int = 0  # the intervals of a clip are reproducible

    def __post_init__(self) -> None:
        if self.replicates < 100:
            raise ConfigError(f"block bootstrap: replicates must be >= 100, got {self.replicates}")
        if not 0.0 < self.level < 1.0:
            raise ConfigError(f"block bootstrap: level must be in (0, 1), got {self.level}")
        if not self.min_block_s > 0:
            raise ConfigError(f"block bootstrap: min_block_s must be > 0, got {self.min_block_s}")


@dataclass(frozen=True)
class ClipInterval:
    """An interval of a clip statistic, or why there is none."""

    low: float  # NaN where none
    high: float
    block: int  # block length in frames (0 where none)
    how: str  # the `interval` column: how it was obtained, or "none: <why>"


def autocovariance(x: np.ndarray, max_lag: int) -> np.ndarray:
    """R(k) = (1/n) sum_t (x_t - mean)(x_{t+k} - mean) for k = 0..max_lag of a series `(n,)` without
    NaN (FFT, so a 10-minute clip is instant)."""
    n = len(x)
    d = x - x.mean()
    size = 1 << int(math.ceil(math.log2(2 * n)))
    spec = np.fft.rfft(d, size)
    acov = np.fft.irfft(spec * np.conj(spec), size)[: max_lag + 1] / n
    return acov


def block_length(x: np.ndarray) -> float:
    """The circular bootstrap's block length for the mean of `x (n,)` (NaN filled with the mean),
    by Politis & White (2004) as corrected by Patton, Politis & White (2009): the flat-top lag
    window's bandwidth from the first run of insignificant autocorrelations, then
    b = (2 G^2 / D_CB)^(1/3) n^(1/3), capped at min(3 sqrt(n), n / 3); 0 for a constant or
    uncorrelated series (the caller's minimum applies)."""
    x = np.where(np.isfinite(x), x, np.nanmean(x)) if np.isfinite(x).any() else np.zeros_like(x)
    n = len(x)
    if n < 8:
        return 0.0
    k_n = max(5, int(math.ceil(math.sqrt(math.log10(n)))))
    m_max = min(n - 1, int(math.ceil(math.sqrt(n))) + k_n)
    acov = autocovariance(x, m_max)
    if acov[0] <= 0:
        return 0.0
    rho = np.abs(acov[1:] / acov[0])  # (m_max,) lags 1..m_max
    small = rho < 2.0 * math.sqrt(math.log10(n) / n)
    # m_hat: the first lag m after which k_n autocorrelations in a row are insignificant
    runs = np.lib.stride_tricks.sliding_window_view(small, k_n).all(axis=1) if len(small) >= k_n else np.zeros(0, bool)
    m_hat = int(np.argmax(runs)) if runs.any() else m_max
    big_m = min(2 * m_hat, m_max)
    if big_m == 0:
        return 0.0
    k = np.arange(1, big_m + 1)
    t = k / big_m
    lam = np.where(t <= 0.5, 1.0, 2.0 * (1.0 - t))  # the flat-top (trapezoid) lag window
    g = 2.0 * np.sum(lam * k * acov[k])
    g0 = acov[0] + 2.0 * np.sum(lam * acov[k])
    d_cb = 4.0 / 3.0 * g0**2
    if d_cb <= 0:
        return 0.0
    b = (2.0 * g**2 / d_cb) ** (1.0 / 3.0) * n ** (1.0 / 3.0)
    return float(min(b, 3.0 * math.sqrt(n), n / 3.0))


def _starts(n: int, block: int, settings: BootstrapSettings) -> np.ndarray:
    """`(B, ceil(n / block))` random block starts on the circle of n frames."""
    rng = np.random.default_rng(settings.seed)
    return rng.integers(0, n, size=(settings.replicates, -(-n // block)))


def _block(series: np.ndarray, fps: float, settings: BootstrapSettings) -> int:
    return max(int(math.ceil(settings.min_block_s * fps)), int(math.ceil(max(block_length(s) for s in series))))


def _method(block: int, fps: float, settings: BootstrapSettings) -> str:
    return (f"block_bootstrap: circular, blocks of {block} frames ({block / fps:.1f} s), "
            f"{settings.replicates} replicates, percentile")  # fmt: skip


def share_intervals(
    indicators: np.ndarray, fps: float, settings: BootstrapSettings | None = None
) -> list[ClipInterval]:
    """Intervals for the shares of C categories over a clip's frames with a call.

    `indicators (C, T)`: per category and frame of the clip's grid, 1 where the frame's call is
    that category, 0 where it is another, NaN where the frame has no call. The shares are
    sum_t ind_c / sum_t called; one resampling serves every category (the replicates' shares add
    up to 1), with the longest of the categories' block lengths.
    """
    settings = settings or BootstrapSettings()
    ind = np.asarray(indicators, dtype=float)  # (C, T)
    called = np.isfinite(ind[0])
    n, count = ind.shape[1], int(called.sum())
    block = _block(ind, fps, settings)
    if count < 2 or n < 2 * block:
        why = f"none: too few frames for a block bootstrap ({count} with a call, blocks of {block})"
        return [ClipInterval(np.nan, np.nan, 0, why) for _ in ind]
    starts = _starts(n, block, settings)  # (B, k)
    ext = np.concatenate([np.where(called, ind, 0.0), np.where(called, ind, 0.0)[:, :block]], axis=1)  # (C, n + b)
    cs = np.concatenate([np.zeros((len(ind), 1)), np.cumsum(ext, axis=1)], axis=1)  # (C, n + b + 1)
    cs_called = np.concatenate([[0.0], np.cumsum(np.concatenate([called, called[:block]]).astype(float))])
    den = (cs_called[starts + block] - cs_called[starts]).sum(axis=1)  # (B,)
    num = (cs[:, starts + block] - cs[:, starts]).sum(axis=2)  # (C, B)
    with np.errstate(invalid="ignore", divide="ignore"):
        shares = num / den  # (C, B); NaN for a replicate without a called frame
    q = [(1.0 - settings.level) / 2.0, (1.0 + settings.level) / 2.0]
    lows, highs = np.nanquantile(shares, q, axis=1)
    how = _method(block, fps, settings)
    return [ClipInterval(float(lo), float(hi), block, how) for lo, hi in zip(lows, highs, strict=True)]


def median_interval(values: np.ndarray, fps: float, settings: BootstrapSettings | None = None) -> ClipInterval:
    """An interval for the median of a clip's values `(T,)` on its frame grid (NaN: no value)."""
    settings = settings or BootstrapSettings()
    values = np.asarray(values, dtype=float)
    known = np.isfinite(values)
    n, count = len(values), int(known.sum())
    block = _block(values[None], fps, settings)
    if count < 2 or n < 2 * block:
        return ClipInterval(np.nan, np.nan, 0, f"none: too few frames for a block bootstrap ({count} with a value, "
                                               f"blocks of {block})")  # fmt: skip
    starts = _starts(n, block, settings)  # (B, k)
    offsets = np.arange(block)
    medians = np.empty(settings.replicates)
    chunk = max(1, (1 << 22) // (starts.shape[1] * block))  # about 4 M gathered values at a time
    for first in range(0, settings.replicates, chunk):
        idx = (starts[first : first + chunk, :, None] + offsets) % n  # (b, k, block)
        taken = values[idx.reshape(len(idx), -1)]  # (b, k * block)
        with np.errstate(all="ignore"):
            medians[first : first + chunk] = _nanmedian_rows(taken)
    q = [(1.0 - settings.level) / 2.0, (1.0 + settings.level) / 2.0]
    low, high = np.nanquantile(medians, q)
    return ClipInterval(float(low), float(high), block, _method(block, fps, settings))


def _nanmedian_rows(x: np.ndarray) -> np.ndarray:
    """The median of each row of `x (R, m)` over its finite entries (NaN for none), by sorting
    (NaN last) and taking the middle of the finite ones: faster than np.nanmedian."""
    s = np.sort(x, axis=1)
    count = np.isfinite(s).sum(axis=1)
    rows = np.arange(len(s))
    lo = np.maximum((count - 1) // 2, 0)
    hi = np.maximum(count // 2, 0)
    med = 0.5 * (s[rows, lo] + s[rows, hi])
    return np.where(count > 0, med, np.nan)
