"""Intervals for clip statistics of frame series whose neighbouring frames are correlated: the
circular block bootstrap (Politis & Romano 1992), percentile intervals.

A clip is one stretch of an infant's behaviour: a head held to one side for seconds gives
hundreds of frames that say the same thing, so a binomial interval over frames taken as
independent is far too narrow. The bootstrap resamples whole blocks of consecutive frames; the
block length is chosen from the series' own autocorrelation (Politis & White 2004, with the
correction of Patton, Politis & White 2009: the circular bootstrap's optimal block), and never
shorter than `min_block_s` seconds of frames (so it is tied to the fps): blocks of `block_factor`
times that length, at most a quarter of the clip (`min_blocks`). The percentile interval's arms
are widened by t(k - 1) / z for k blocks and by the blocks' taper (`taper_correction`): both
correct the too narrow intervals of clips of few stretches of behaviour, not wholly (coverage
below 90 % for clips of a few minutes with long holds). The interval is for the long-run share
(or median) of the process the clip was drawn from, and knows nothing of the frames' own errors:
`head_calibration` widens it to its measured coverage (`benchmarks/calibrate/head_measures.py`,
docs/clinical.md, "Head").

Series lie on the clip's frame grid (`frame - first frame`), NaN where a frame has no value (not in
the result, or no call): a replicate's share is the ratio of its blocks' counts, so gaps keep their
place in time (a median closes them: `median_interval`). Vectorised: a replicate is a row of block
starts, a block's count a difference of cumulative sums (shares); medians gather the replicate's
values in chunks of replicates.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from statistics import NormalDist

import numpy as np

from ...errors import ConfigError


@dataclass(frozen=True)
class BootstrapSettings:
    """The block bootstrap's settings (recorded with every interval it gives)."""

    replicates: int = 1000
    level: float = 0.9
    min_block_s: float = 1.0  # blocks hold at least this many seconds of frames
    block_factor: float = 2.0  # blocks of this many times the Politis-White length (coverage over its MSE)
    min_blocks: int = 4  # a clip shorter than this many blocks gets no interval
    seed: int = 0  # the intervals of a clip are reproducible

    def __post_init__(self) -> None:
        if self.replicates < 100:
            raise ConfigError(f"block bootstrap: replicates must be >= 100, got {self.replicates}")
        if not 0.0 < self.level < 1.0:
            raise ConfigError(f"block bootstrap: level must be in (0, 1), got {self.level}")
        if not self.min_block_s > 0 or not self.block_factor > 0:
            raise ConfigError(
                f"block bootstrap: min_block_s and block_factor must be > 0, got {self.min_block_s}, "
                f"{self.block_factor}"
            )
        if self.min_blocks < 4:
            raise ConfigError(f"block bootstrap: min_blocks must be >= 4, got {self.min_blocks}")


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


def taper_correction(x: np.ndarray, block: int) -> float:
    """How much wider a block bootstrap interval of the mean of `x (n,)` (NaN filled with the mean)
    must be, as a factor on its standard error: blocks of b frames estimate the long-run variance
    with Bartlett's taper, sum_{|k|<b} (1 - |k|/b) R(k), short by sum_{|k|<b} |k| R(k) / b (the
    block bootstrap's first-order bias, Kuensch 1989); the factor is the square root of the
    untapered sum over the tapered one, between 1 and 2."""
    x = np.where(np.isfinite(x), x, np.nanmean(x)) if np.isfinite(x).any() else np.zeros_like(x)
    if block < 2 or len(x) <= block:
        return 1.0
    acov = autocovariance(x, block - 1)
    k = np.arange(1, block)
    flat = acov[0] + 2.0 * acov[k].sum()
    tapered = acov[0] + 2.0 * ((1.0 - k / block) * acov[k]).sum()
    if not (tapered > 0 and flat > tapered):
        return 1.0
    return float(min(2.0, math.sqrt(flat / tapered)))


def _starts(n: int, block: int, settings: BootstrapSettings) -> np.ndarray:
    """`(B, ceil(n / block))` random block starts on the circle of n frames."""
    rng = np.random.default_rng(settings.seed)
    return rng.integers(0, n, size=(settings.replicates, -(-n // block)))


def _block(series: np.ndarray, fps: float, settings: BootstrapSettings) -> int:
    """`block_factor` times the longest Politis-White length of `series (C, n)`, at most n /
    `min_blocks` frames, and at least `min_block_s` seconds of frames (which wins)."""
    longest = max(block_length(s) for s in series)
    n = series.shape[1]
    wanted = min(settings.block_factor * longest, n / settings.min_blocks)
    return max(int(math.ceil(settings.min_block_s * fps)), int(math.floor(wanted)))


def t_quantile(p: float, df: float) -> float:
    """Student's t quantile (Cornish-Fisher expansion about the normal one, Abramowitz & Stegun
    26.7.5: within 0.01 of the exact value for df >= 3, the smallest `min_blocks` allows)."""
    z = NormalDist().inv_cdf(p)
    terms = ((z**3 + z) / 4, (5 * z**5 + 16 * z**3 + 3 * z) / 96, (3 * z**7 + 19 * z**5 + 17 * z**3 - 15 * z) / 384,
             (79 * z**9 + 776 * z**7 + 1482 * z**5 - 1920 * z**3 - 945 * z) / 92160)  # fmt: skip
    return z + sum(term / df ** (k + 1) for k, term in enumerate(terms))


def _interval(estimate: float, replicates: np.ndarray, blocks: int, taper: float,
              settings: BootstrapSettings) -> tuple[float, float]:  # fmt: skip
    """The percentile interval's two arms about the estimate, each widened by t(k - 1) / z for a
    clip of k blocks (a few blocks are a few independent stretches of behaviour, and the
    percentile interval alone is calibrated like a normal one) and by `taper_correction`."""
    upper = (1.0 + settings.level) / 2.0
    lo, hi = np.nanquantile(replicates, [1.0 - upper, upper])
    widen = taper * t_quantile(upper, blocks - 1) / NormalDist().inv_cdf(upper)
    return estimate - widen * (estimate - lo), estimate + widen * (hi - estimate)


def _method(block: int, blocks: int, fps: float, settings: BootstrapSettings) -> str:
    return (
        f"circular block bootstrap, {blocks} blocks of {block} frames ({block / fps:.1f} s), "
        f"{settings.replicates} replicates, percentile widened by t({blocks - 1})/z and the blocks' taper"
    )


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
    if count < 2 or n < settings.min_blocks * block:
        why = (f"none: too few frames for a block bootstrap ({n} frames, {count} with a call; "
               f"{settings.min_blocks} blocks of {block} needed)")  # fmt: skip
        return [ClipInterval(np.nan, np.nan, 0, why) for _ in ind]
    starts = _starts(n, block, settings)  # (B, k)
    ext = np.concatenate([np.where(called, ind, 0.0), np.where(called, ind, 0.0)[:, :block]], axis=1)  # (C, n + b)
    cs = np.concatenate([np.zeros((len(ind), 1)), np.cumsum(ext, axis=1)], axis=1)  # (C, n + b + 1)
    cs_called = np.concatenate([[0.0], np.cumsum(np.concatenate([called, called[:block]]).astype(float))])
    den = (cs_called[starts + block] - cs_called[starts]).sum(axis=1)  # (B,)
    num = (cs[:, starts + block] - cs[:, starts]).sum(axis=2)  # (C, B)
    with np.errstate(invalid="ignore", divide="ignore"):
        shares = num / den  # (C, B); NaN for a replicate without a called frame
    blocks = starts.shape[1]
    how = _method(block, blocks, fps, settings)
    out = []
    for c in range(len(ind)):
        estimate = float(np.where(called, ind[c], 0.0).sum() / count)
        lo, hi = _interval(estimate, shares[c], blocks, taper_correction(ind[c], block), settings)
        out.append(ClipInterval(max(0.0, lo), min(1.0, hi), block, how))
    return out


def median_interval(values: np.ndarray, fps: float, settings: BootstrapSettings | None = None) -> ClipInterval:
    """An interval for the median of a clip's values `(T,)` on its frame grid (NaN: no value).

    The frames with a value are taken in time order and the gaps closed (a median has no ratio
    form to keep them), so every replicate has as many values and the medians are one
    `np.median` over a chunk of replicates."""
    settings = settings or BootstrapSettings()
    values = np.asarray(values, dtype=float)
    known = values[np.isfinite(values)]  # (n,) in time order
    n = len(known)
    block = _block(known[None], fps, settings)
    if n < settings.min_blocks * block:
        return ClipInterval(np.nan, np.nan, 0, f"none: too few frames for a block bootstrap ({n} with a value; "
                                               f"{settings.min_blocks} blocks of {block} needed)")  # fmt: skip
    starts = _starts(n, block, settings).astype(np.int32)  # (B, k)
    ext = np.concatenate([known, known[:block]])  # the circle, unrolled: no modulo per value
    offsets = np.arange(block, dtype=np.int32)
    medians = np.empty(settings.replicates)
    chunk = max(1, (1 << 22) // (starts.shape[1] * block))  # about 4 M gathered values at a time
    for first in range(0, settings.replicates, chunk):
        idx = starts[first : first + chunk, :, None] + offsets  # (c, k, block)
        medians[first : first + chunk] = np.median(ext[idx.reshape(len(idx), -1)], axis=1)
    blocks = starts.shape[1]
    median = float(np.median(known))
    taper = taper_correction((known <= median).astype(float), block)  # the median's influence: a side of it
    low, high = _interval(median, medians, blocks, taper, settings)
    return ClipInterval(float(low), float(high), block, _method(block, blocks, fps, settings))
