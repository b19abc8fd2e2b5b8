"""The shared statistics: one split-conformal quantile and one Pearson's r for the whole package."""

from __future__ import annotations

import numpy as np
import pytest

from zedo_cli.stats import TooFewCases, conformal_quantile, min_cases, pearson, require_quantile


def test_the_conformal_quantile_is_the_finite_sample_rank() -> None:
    assert conformal_quantile(np.arange(1.0, 11.0), 0.9) == 10.0  # ceil(11 * 0.9) = 10th of 10
    assert conformal_quantile(np.arange(1.0, 101.0), 0.9) == 91.0
    assert conformal_quantile(np.array([np.nan, 2.0, 1.0]), 0.5) == 2.0  # NaN left out
    assert conformal_quantile(np.array([1.0, np.inf, 3.0, 2.0]), 0.5) == 2.0  # inf left out: 3 scores, rank 2
    assert conformal_quantile(np.array([1.0, np.inf, 3.0, 2.0]), 0.75, keep_infinite=True) == np.inf


@pytest.mark.parametrize(("level", "needed"), [(0.5, 1), (0.8, 4), (0.9, 9), (0.95, 19)])
def test_too_few_cases_give_nan_never_the_largest_score_nor_infinity(level: float, needed: int) -> None:
    assert min_cases(level) == needed
    assert np.isfinite(conformal_quantile(np.arange(1.0, needed + 1.0), level))
    assert np.isnan(conformal_quantile(np.arange(1.0, float(needed)), level))
    assert np.isnan(conformal_quantile(np.array([]), level))
    with pytest.raises(TooFewCases, match=f"the knee: too few calibration cases \\({needed - 1}; a {level:g} quantile"):
        require_quantile(np.arange(1.0, float(needed)), level, "the knee")


def test_the_quantile_covers_fresh_cases_at_its_level() -> None:
    rng = np.random.default_rng(1)
    hits = [rng.exponential() <= conformal_quantile(rng.exponential(size=19), 0.9) for _ in range(2000)]
    assert 0.88 <= np.mean(hits) <= 0.93  # exactly 0.9 in expectation: rank 18 of 20


def test_pearson_is_pairwise_complete_and_undefined_when_constant() -> None:
    a, b = np.array([1.0, 2.0, 3.0, np.nan]), np.array([2.0, 4.0, 7.0, 1.0])
    assert pearson(a, b) == pytest.approx(np.corrcoef(a[:3], b[:3])[0, 1])
    assert np.isnan(pearson(np.array([0.1, 0.1, 0.1]), np.array([1.0, 2.0, 3.0])))
    assert np.isnan(pearson(a, b, min_count=4))  # three known pairs
    assert np.isnan(pearson(np.array([1.0]), np.array([2.0])))
