"""Movement features of angle series, and 90 % intervals from per-joint radii."""

from __future__ import annotations

import numpy as np
import pytest
from analysis_poses import SKEL, set_limb, standing, to_array

from zedo_cli.analysis.analyse import all_measures
from zedo_cli.analysis.movement import angular_velocity, left_right_correlation, series_features
from zedo_cli.analysis.symmetry import symmetry_angles
from zedo_cli.analysis.uncertainty import CHI3_Q90, sample_intervals


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


def test_the_chi3_constant_is_the_90_percent_radius_of_a_3d_gaussian() -> None:
    norms = np.linalg.norm(np.random.default_rng(0).standard_normal((400_000, 3)), axis=1)
    assert (norms <= CHI3_Q90).mean() == pytest.approx(0.90, abs=0.002)


def _pose_with_bent_knee(bend: float) -> np.ndarray:
    pts = standing()
    set_limb(pts, "left", "leg", 0.0, 0.0, bend=bend)
    return to_array(pts)


def test_zero_radius_gives_a_point_interval_and_unknown_radius_none() -> None:
    pose = _pose_with_bent_knee(40.0)[None]
    radii = np.zeros((1, 12))
    radii[0, SKEL.index("right_wrist")] = np.nan
    out = sample_intervals(pose, radii, lambda p: all_measures(p, SKEL), samples=200)
    low, high = out["symmetry_shank_deg"]
    assert low[0] == pytest.approx(40.0) and high[0] == pytest.approx(40.0)
    assert np.isnan(out["symmetry_forearm_deg"][0][0])  # uses the right wrist
    assert np.isfinite(out["symmetry_upper_arm_deg"][0][0])


def test_intervals_are_seeded_and_grow_with_the_radius() -> None:
    pose = _pose_with_bent_knee(40.0)[None]
    f = lambda p: symmetry_angles(p, SKEL)  # noqa: E731
    a = sample_intervals(pose, np.full((1, 12), 0.01), f, seed=3)
    b = sample_intervals(pose, np.full((1, 12), 0.01), f, seed=3)
    c = sample_intervals(pose, np.full((1, 12), 0.03), f, seed=3)
    assert a["symmetry_shank_deg"][0] == b["symmetry_shank_deg"][0]
    width = {k: v[1] - v[0] for k, v in (("a", a["symmetry_shank_deg"]), ("c", c["symmetry_shank_deg"]))}
    assert 0 < width["a"][0] < width["c"][0]
    assert a["symmetry_shank_deg"][0][0] < 40.0 < a["symmetry_shank_deg"][1][0]


@pytest.mark.parametrize("bend", [0.0, 10.0, 40.0])
def test_the_interval_covers_the_true_measure_about_90_percent_of_the_time(bend: float) -> None:
    """Truth + isotropic Gaussian joint errors whose 90 % radius is r -> the reported pose and
    its radii; the interval around the reported pose must hold the true measure ~90 % of the
    time, also at a true 0 (a symmetric pair), where the plain percentile interval never does."""
    rng = np.random.default_rng(1)
    truth = _pose_with_bent_knee(bend)
    sigma = 0.004  # metres; radius r = 2.5 sigma = 1 cm around 10 cm segments
    trials = 300
    reported = truth[None] + rng.normal(0.0, sigma, (trials, 12, 3))
    radii = np.full((trials, 12), sigma * CHI3_Q90)
    out = sample_intervals(reported, radii, lambda p: symmetry_angles(p, SKEL), samples=400, seed=0,
                           ranges={"symmetry_shank_deg": (0.0, 180.0)})  # fmt: skip
    true = float(symmetry_angles(truth[None], SKEL)["symmetry_shank_deg"][0])
    low, high = out["symmetry_shank_deg"]
    covered = ((low <= true) & (true <= high)).mean()
    assert 0.8 <= covered <= 0.96, covered
    assert (low >= 0).all()


def test_a_reported_zero_keeps_a_real_interval() -> None:
    """A perfectly symmetric reported pose: the reflected interval alone would be [0, 0]."""
    pose = _pose_with_bent_knee(0.0)[None]
    out = sample_intervals(pose, np.full((1, 12), 0.01), lambda p: symmetry_angles(p, SKEL), samples=500,
                           ranges={"symmetry_shank_deg": (0.0, 180.0)})  # fmt: skip
    low, high = out["symmetry_shank_deg"]
    assert low[0] == 0.0 and 5.0 < high[0] < 40.0
