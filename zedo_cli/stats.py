"""Statistics every calibration and measure shares: the split-conformal quantile, Pearson's r and the
intraclass correlation of a test and a retest.

One definition each, so that an interval fitted in one place and checked in another cannot disagree.
numpy only.
"""

from __future__ import annotations

import numpy as np

TOO_FEW_CASES = "too few calibration cases"


class TooFewCases(ValueError):
    """A conformal quantile asked of fewer cases than its level needs."""


def conformal_rank(count: int, level: float) -> int:
    """The rank of the split-conformal quantile among `count` scores: ceil((count + 1) level)."""
    return int(np.ceil((count + 1) * level))


def min_cases(level: float) -> int:
    """The fewest scores whose split-conformal quantile at `level` exists (0.9: 9; 0.95: 19)."""
    count = 1
    while conformal_rank(count, level) > count:
        count += 1
    return count


def conformal_quantile(scores: np.ndarray, level: float, *, keep_infinite: bool = False) -> float:
    """The split-conformal quantile of `scores (n,)`: the ceil((n + 1) level)-th smallest.

    NaN scores are left out, and infinite ones too unless `keep_infinite` (a score that no finite
    width reaches still counts among the n). Fewer scores than the level needs give NaN: no
    interval is backed then, never the largest score (too narrow) nor infinity (no interval in
    disguise); `TOO_FEW_CASES` is the reason to state."""
    scores = np.asarray(scores, dtype=float)
    kept = np.sort(scores[~np.isnan(scores) if keep_infinite else np.isfinite(scores)])
    rank = conformal_rank(len(kept), level)
    return float(kept[rank - 1]) if 0 < rank <= len(kept) else float("nan")


def require_quantile(scores: np.ndarray, level: float, what: str) -> float:
    """`conformal_quantile`, raising `TooFewCases` naming `what` where it would be NaN (for fitting code
    that must not write a calibration it cannot back)."""
    q = conformal_quantile(scores, level)
    if np.isnan(q):
        count = int(np.isfinite(np.asarray(scores, dtype=float)).sum())
        raise TooFewCases(f"{what}: {TOO_FEW_CASES} ({count}; a {level:g} quantile needs {min_cases(level)})")
    return q


def pearson(a: np.ndarray, b: np.ndarray, *, min_count: int = 2) -> float:
    """Pearson's r of `a (n,)` and `b (n,)` over the positions where both are known; NaN with fewer than
    `min_count` (at least 2) such positions or where either is constant there (pandas `corr`)."""
    ok = np.isfinite(a) & np.isfinite(b)
    if ok.sum() < max(2, min_count) or np.ptp(a[ok]) == 0 or np.ptp(b[ok]) == 0:
        return np.nan
    x, y = a[ok] - a[ok].mean(), b[ok] - b[ok].mean()
    den = np.sqrt((x * x).sum() * (y * y).sum())
    return float((x * y).sum() / den) if den > 0 else np.nan


def icc_agreement(measurements: np.ndarray) -> float:
    """ICC(2,1) of `measurements (n, k)`, n subjects each measured k times: two-way random effects, absolute
    agreement, one measurement (Shrout & Fleiss 1979; Koo & Li 2016). Rows with a NaN are left out; NaN with
    fewer than 3 complete rows or no variation at all."""
    x = np.asarray(measurements, dtype=float)
    x = x[np.isfinite(x).all(axis=1)]
    n, k = x.shape
    if n < 3 or k < 2:
        return float("nan")
    grand = x.mean()
    rows = k * ((x.mean(axis=1) - grand) ** 2).sum() / (n - 1)
    cols = n * ((x.mean(axis=0) - grand) ** 2).sum() / (k - 1)
    resid = x - x.mean(axis=1, keepdims=True) - x.mean(axis=0, keepdims=True) + grand
    error = (resid**2).sum() / ((n - 1) * (k - 1))
    den = rows + (k - 1) * error + k * (cols - error) / n
    return float((rows - error) / den) if den > 0 else float("nan")
