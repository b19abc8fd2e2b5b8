"""The pandas-1.x semantics that the published clip features rely on, written out in numpy: window
alignment at odd and even windows, NaN edges, interpolation, and the statistics, against hand values."""

from __future__ import annotations

import numpy as np
import pytest

from zedo_cli.analysis.clip.series import (
    circular_mean_deg,
    circular_variance,
    entropy_of_rounded,
    interpolate_gaps,
    iqr,
    rolling_centered,
    rolling_trailing_mean,
    shortest_turn_deg,
    step_difference,
)
from zedo_cli.stats import pearson

NAN = np.nan
SQUARES = np.arange(10.0) ** 2  # 0, 1, 4, 9, ..., 81


def test_centred_odd_window_is_symmetric_with_nan_edges() -> None:
    # w = 3: frame i averages i - 1 .. i + 1; the first and last frames lack a full window
    want = [NAN] + [(SQUARES[i - 1] + SQUARES[i] + SQUARES[i + 1]) / 3 for i in range(1, 9)] + [NAN]
    np.testing.assert_allclose(rolling_centered(SQUARES, 3, "mean"), want)
    np.testing.assert_array_equal(rolling_centered(SQUARES, 3, "median"), [NAN, *SQUARES[1:9], NAN])


def test_centred_even_window_takes_one_more_frame_before() -> None:
    # w = 4 (pandas center=True): frame i uses i - 2 .. i + 1, so frames 0, 1 and 9 are NaN
    mean = rolling_centered(SQUARES, 4, "mean")
    np.testing.assert_allclose(mean, [NAN, NAN, 3.5, 7.5, 13.5, 21.5, 31.5, 43.5, 57.5, NAN])
    median = rolling_centered(SQUARES, 4, "median")  # the mean of the two middle values: (1 + 4) / 2 at frame 2
    np.testing.assert_allclose(median, [NAN, NAN, 2.5, 6.5, 12.5, 20.5, 30.5, 42.5, 56.5, NAN])


def test_a_nan_anywhere_in_a_window_empties_it_and_columns_are_independent() -> None:
    x = np.stack([np.arange(8.0), np.arange(8.0)], 1)
    x[3, 0] = NAN
    med = rolling_centered(x, 3, "median")
    np.testing.assert_array_equal(np.isnan(med[:, 0]), [1, 0, 1, 1, 1, 0, 0, 1])
    np.testing.assert_array_equal(med[1:7, 1], np.arange(1.0, 7.0))
    assert np.isnan(rolling_centered(np.arange(3.0), 5, "mean")).all()  # shorter than the window


def test_trailing_mean_and_step_difference() -> None:
    np.testing.assert_allclose(rolling_trailing_mean(np.arange(5.0), 2), [NAN, 0.5, 1.5, 2.5, 3.5])
    np.testing.assert_array_equal(step_difference(np.array([1.0, 4.0, NAN, 5.0])), [0.0, 3.0, NAN, NAN])
    np.testing.assert_array_equal(step_difference(np.array([NAN, 2.0, 3.0])), [NAN, NAN, 1.0])


def test_interpolation_fills_inside_and_after_but_not_before() -> None:
    got = interpolate_gaps(np.array([NAN, NAN, 1.0, NAN, 3.0, NAN, NAN]))
    np.testing.assert_array_equal(got, [NAN, NAN, 1.0, 2.0, 3.0, 3.0, 3.0])
    two = interpolate_gaps(np.array([[0.0, NAN], [NAN, NAN], [NAN, 5.0], [6.0, NAN]]))  # per column
    np.testing.assert_allclose(two, [[0, NAN], [2, NAN], [4, 5], [6, 5]])
    assert np.isnan(interpolate_gaps(np.full(4, NAN))).all()


def test_shortest_turn_wraps_and_keeps_half_turns() -> None:
    prev, cur = np.array([350.0, 10.0, 0.0, 180.0, 90.0]), np.array([10.0, 350.0, 180.0, 0.0, 100.0])
    np.testing.assert_array_equal(shortest_turn_deg(prev, cur), [20.0, -20.0, 180.0, -180.0, 10.0])


def test_statistics() -> None:
    assert circular_mean_deg(np.array([350.0, 10.0, NAN])) == pytest.approx(0.0, abs=1e-12)
    assert circular_variance(np.array([0.0, 180.0])) == pytest.approx(1.0)
    assert circular_variance(np.array([30.0, 30.0])) == pytest.approx(0.0, abs=1e-12)
    assert entropy_of_rounded(np.array([1.2, 0.8, 2.4, 1.6, NAN]), 0) == pytest.approx(np.log(2))  # 1, 1, 2, 2
    assert entropy_of_rounded(np.array([0.125, 0.135]), 2) == pytest.approx(np.log(2))  # 0.12, 0.14 (half to even)
    assert np.isnan(entropy_of_rounded(np.full(3, NAN), 2))  # nothing known: no entropy (published: 0)
    assert iqr(np.array([1.0, 2.0, 3.0, 4.0, 5.0, NAN])) == pytest.approx(2.0)
    assert iqr(np.array([0.0, 10.0])) == pytest.approx(5.0)  # 7.5 - 2.5, linear between the two
    assert pearson(np.array([1.0, 2.0, 3.0, NAN]), np.array([2.0, 4.0, 7.0, 1.0])) == pytest.approx(0.9933, abs=1e-4)
    assert np.isnan(pearson(np.array([0.1, 0.1, 0.1]), np.array([1.0, 2.0, 3.0])))  # constant: undefined
