"""The share of a clip's frames in which a symmetry pair is asymmetric, with an interval.

What it estimates: of one person's frames with a calibrated value, the share whose TRUE symmetry
angle exceeds the threshold. Each frame's calibration (analysis.calibration) gives a conformal
distribution of the truth around its estimate; its ends at the levels of LEVELS are its quantiles
((1 - level) / 2 below, (1 + level) / 2 above). Through them, linear between, the frame's
probability of being asymmetric, p_t = P(truth_t > threshold), is read off where the threshold
falls (`probability_above`: the level at which the frame's interval touches the threshold). The
share's estimate is the mean of p_t.

The interval is not binomial: a frame's error is the error of its neighbours too (the same limb
pointing at the camera for a second, the temporal filter). `share_interval` draws each frame's
truth from its distribution with the frames' positions in their distributions (uniform ranks u)
shared within blocks of `block` consecutive frames and independent between blocks, block
boundaries placed at random per draw (a moving-block bootstrap of the ranks): a frame is
asymmetric in a draw when u < p_t. The interval holds the middle `level` of the drawn shares.

The block length, in frames, is what keeps errors correlated: `block_frames` takes the longer of
the calibrated error persistence (ERROR_PERSISTENCE_S seconds, measured on held-out clips) and
the clip's own: the integrated autocorrelation time of the frames' probabilities, so that a clip
in which the infant holds a posture for a minute is one block of a minute, not 60 of a second.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .calibration import MeasureModel

# Seconds over which a frame's error persists. Measured on held-out synthetic clips
# (benchmarks/calibrate/calibrate_measures.py --cameras; docs/clinical.md) as the integrated autocorrelation time
# of the ranks of the truth in the frames' calibrated distributions: median 0.47-0.56 s, 90th percentile
# 0.79-0.95 s over the camera kinds; the 90th percentile, rounded up. A clip's own persistence, when longer,
# wins (block_frames).
ERROR_PERSISTENCE_S = 1.0
DRAWS = 2000  # bootstrap draws per clip and pair
MAX_PHASES = 16  # distinct block offsets per clip (the draws share them)
_FAR = 360.0  # degrees: where an infinite conformal quantile (a bin too small) puts the distribution's end


@dataclass(frozen=True)
class Share:
    """A clip's share of frames asymmetric: the estimate, its interval at `level`, the frames it is over."""

    value: float
    low: float
    high: float
    frames: int
    block: int  # frames per block of the bootstrap


def probability_above(model: MeasureModel, value: np.ndarray, threshold: float | np.ndarray) -> np.ndarray:
    """P(truth > threshold) `(n,)` for raw measured values `(n,)` (degrees) under `model`: the model's
    distribution of the truth around the estimate (its interval ends at every level as quantiles, linear
    between them, and linear beyond the widest level out to where it reaches 0 and 1). `threshold`:
    degrees, one or one per value."""
    value = np.asarray(value, dtype=float)
    threshold = np.broadcast_to(np.asarray(threshold, dtype=float), value.shape)
    est = model.estimate(value)
    bins = model.bins(value)
    levels = sorted(model.q_high)
    cdf = np.array([0.0] + [(1 - lv) / 2 for lv in reversed(levels)] + [(1 + lv) / 2 for lv in levels] + [1.0])
    out = np.full(len(value), np.nan)
    for b in np.unique(bins):
        low = np.array([-min(model.q_low[lv][b], _FAR) for lv in reversed(levels)])  # ascending offsets
        high = np.array([min(model.q_high[lv][b], _FAR) for lv in levels])
        # the widest level's tail continued with its outer slope to probability 0 and 1
        lo_end = low[0] - (low[1] - low[0]) * cdf[1] / (cdf[2] - cdf[1]) if len(levels) > 1 else low[0] - 1.0
        hi_end = high[-1] + (high[-1] - high[-2]) * cdf[1] / (cdf[2] - cdf[1]) if len(levels) > 1 else high[-1] + 1.0
        knots = np.maximum.accumulate(np.concatenate([[lo_end], low, high, [hi_end]]))
        sel = bins == b
        out[sel] = 1.0 - np.interp(threshold[sel] - est[sel], knots, cdf)
    return out


def integrated_autocorrelation(x: np.ndarray) -> float:
    """The integrated autocorrelation time of a series `(n,)` in samples: 1 + 2 * the sum of its
    autocorrelations up to the first that is not positive (1 for a constant or white series)."""
    x = np.asarray(x, dtype=float)
    n = len(x)
    d = x - x.mean()
    var = float((d * d).sum())
    if n < 3 or var <= 1e-12 * n:
        return float(n) if n and var <= 1e-12 * n else 1.0  # a constant series is one block
    size = 1 << int(np.ceil(np.log2(2 * n)))
    f = np.fft.rfft(d, size)
    acf = np.fft.irfft(f * np.conj(f), size)[:n] / var  # acf[0] = 1
    stop = np.flatnonzero(acf[1:] <= 0)
    last = int(stop[0]) if len(stop) else n - 1
    return float(1.0 + 2.0 * acf[1 : 1 + last].sum())


def block_frames(p: np.ndarray, fps: float) -> int:
    """Frames per bootstrap block: the longer of ERROR_PERSISTENCE_S at `fps` and the integrated
    autocorrelation time of the frames' probabilities `p (n,)`, at most the clip."""
    own = integrated_autocorrelation(p)
    return int(np.clip(np.ceil(max(ERROR_PERSISTENCE_S * fps, own)), 1, max(len(p), 1)))


def share_interval(p: np.ndarray, block: int, level: float, *, draws: int = DRAWS, seed: int = 0) -> Share:
    """The share of frames asymmetric (the mean of the frames' probabilities `p (n,)`, in time order)
    and its interval at `level`: the middle `level` of the shares drawn with ranks shared within
    blocks of `block` frames at random offsets (see the module's docstring). Vectorised: per offset one
    sort of the frames by (block, p), then per draw one search per block."""
    p = np.asarray(p, dtype=float)
    n = len(p)
    if n == 0:
        return Share(np.nan, np.nan, np.nan, 0, block)
    rng = np.random.default_rng(seed)
    block = int(max(1, min(block, n)))
    phases = rng.choice(block, size=min(block, MAX_PHASES), replace=False)
    per_phase = np.full(len(phases), draws // len(phases))
    per_phase[: draws - per_phase.sum()] += 1
    shares = []
    t = np.arange(n)
    for phase, count in zip(phases, per_phase, strict=True):
        ids = (t + phase) // block  # (n,) block of each frame
        blocks = int(ids[-1]) + 1
        keys = np.sort(2.0 * ids + p)  # block k's frames in [2k, 2k + 1], by p
        ends = np.searchsorted(keys, 2.0 * np.arange(blocks) + 1.0, side="right")  # (blocks,)
        u = rng.random((int(count), blocks))  # one rank per block and draw
        starts = np.searchsorted(keys, 2.0 * np.arange(blocks) + u, side="right")  # frames with p <= u
        shares.append((ends - starts).sum(1) / n)  # frames with p > u: asymmetric in this draw
    drawn = np.concatenate(shares)
    low, high = np.quantile(drawn, [(1 - level) / 2, (1 + level) / 2])
    value = float(p.mean())
    return Share(value, float(min(low, value)), float(max(high, value)), n, block)
