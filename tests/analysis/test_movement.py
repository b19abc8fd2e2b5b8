"""Movement features of angle series, and 90 % intervals from per-joint radii."""

from __future__ import annotations

import numpy as np
import pytest

from zedo_cli.analysis.clip.movement import angular_velocity, left_right_correlation, series_features


def test_sine_series_features_match_the_analytic_values() -> None:
    fps, amp, freq = 1000.0, 20.0, 0.5  # 20 s: 10 whole cycles, 2000 frames a cycle
    frames = np.arange(20000)
    theta = 40.0 + amp * np.sin(2 * np.pi * freq * frames / fps)
    f = series_features(frames, theta, fps)
    peak = 2 * np.pi * freq * amp  # deg/s; |v| = peak |cos|, whose median over a cycle is cos(pi/4)
    assert f["median_abs_velocity"] == pytest.approx(peak * np.cos(np.pi / 4), rel=0.01)
    # IQR of peak |cos|: quantiles at phases 3pi/8 and pi/8
    assert f["abs_velocity_iqr"] == pytest.approx(peak * (np.cos(np.pi / 8) - np.cos(3 * np.pi / 8)), rel=0.02)
    assert f["range"] == pytest.approx(2 * amp, rel=1e-3)


def test_velocity_bridges_gaps_and_wraps() -> None:
    frames = np.array([0, 1, 3, 4])
    theta = np.array([10.0, 12.0, np.nan, 16.0])
    np.testing.assert_allclose(angular_velocity(frames, theta, 10.0), [20.0, 13.333333], rtol=1e-6)
    wrapped = angular_velocity(np.array([0, 1]), np.array([265.0, -85.0]), 1.0)  # 265 == -95: +10 deg
    np.testing.assert_allclose(wrapped, [10.0])


def test_too_short_series_give_nan() -> None:
    f = series_features(np.arange(4), np.array([1.0, np.nan, np.nan, 2.0]), 30.0)
    assert all(np.isnan(v) for v in f.values())


def test_left_right_correlation() -> None:
    t = np.linspace(0, 10, 200)
    left = np.sin(t)
    assert left_right_correlation(left, 3 * left + 5) == pytest.approx(1.0)
    assert left_right_correlation(left, -left) == pytest.approx(-1.0)
    assert abs(left_right_correlation(left, np.cos(3.7 * t))) < 0.2
    assert np.isnan(left_right_correlation(left, np.ones_like(left)))  # a constant side
