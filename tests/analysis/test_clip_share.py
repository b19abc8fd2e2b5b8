"""The clip-level share of frames asymmetric: each frame's probability from its
calibrated distribution, an interval that holds its level when neighbouring frames err together
(where a binomial one does not), and clip rows that agree with the frame rows."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from analysis_results import kicking_poses, result_document, write_document
from test_calibration import PARAMS, calibration

from zedo_cli.analysis.analyse import SYMMETRY_NAMES, AnalysisSettings, analyse, probability_name
from zedo_cli.analysis.pose.symmetry import CALLS
from zedo_cli.analysis.uncertainty.calibration import LEVELS, MeasureModel
from zedo_cli.analysis.uncertainty.clip_share import (
    block_frames,
    integrated_autocorrelation,
    probability_above,
    share_interval,
)
from zedo_cli.analysis.uncertainty.share_calibration import (
    SHARE_CALIBRATED,
    ShareMargin,
    bundled_share_margins,
    share_margin,
)
from zedo_cli.formats.readers.result import read_result


def normal_cdf(x: float) -> float:
    return 0.5 * (1.0 + math.erf(x / math.sqrt(2.0)))


def normal_quantile(q: float) -> float:
    lo, hi = -10.0, 10.0
    for _ in range(80):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if normal_cdf(mid) < q else (lo, mid)
    return (lo + hi) / 2


def gaussian_model(sigma: float) -> MeasureModel:
    """Intervals of a Gaussian error of `sigma` degrees around the measured value, at every level."""
    q = {lv: (sigma * normal_quantile((1 + lv) / 2),) for lv in LEVELS}
    return MeasureModel(0.0, 1.0, (), q, q, circular=False)


def test_a_frames_probability_is_where_its_calibrated_distribution_puts_the_threshold() -> None:
    model = gaussian_model(10.0)
    values = np.linspace(0.0, 56.0, 29)
    p = probability_above(model, values, 28.0)
    expected = np.array([1 - normal_cdf((28.0 - v) / 10.0) for v in values])
    assert np.abs(p - expected).max() < 0.03  # linear between the levels' quantiles
    assert p[0] < 0.01 and p[-1] > 0.99 and np.all(np.diff(p) >= 0)
    assert probability_above(model, np.array([28.0]), 28.0)[0] == pytest.approx(0.5)
    per_value = probability_above(model, np.array([20.0, 20.0]), np.array([20.0, 40.0]))  # one threshold each
    assert per_value[0] == pytest.approx(0.5) and per_value[1] < 0.05


def test_the_integrated_autocorrelation_time() -> None:
    rng = np.random.default_rng(0)
    assert integrated_autocorrelation(rng.normal(size=5000)) == pytest.approx(1.0, abs=0.3)
    ar = np.zeros(20000)
    for t in range(1, len(ar)):  # AR(1), rho 0.9: (1 + rho) / (1 - rho) = 19
        ar[t] = 0.9 * ar[t - 1] + rng.normal()
    assert integrated_autocorrelation(ar) == pytest.approx(19.0, rel=0.25)
    assert integrated_autocorrelation(np.full(50, 0.3)) == 50.0  # a held posture: one block
    assert block_frames(rng.random(300), 30.0) == 30  # at least ERROR_PERSISTENCE_S of frames


def test_sure_frames_make_an_exact_share() -> None:
    p = np.r_[np.zeros(70), np.ones(30)]
    s = share_interval(p, 10, 0.9)
    assert (s.value, s.low, s.high, s.frames) == (0.3, 0.3, 0.3, 100)


def correlated_clip(rng: np.random.Generator, n: int, segment: int) -> tuple[np.ndarray, float]:
    """Frame probabilities `(n,)` drifting over the clip, and the true share of one clip whose frames' truths
    share their rank within segments of about `segment` frames (errors that persist)."""
    t = np.arange(n)
    p = np.clip(0.5 + 0.4 * np.sin(2 * np.pi * t / n * rng.uniform(0.5, 2) + rng.uniform(0, 6)), 0, 1)
    cuts = np.cumsum(rng.integers(segment // 2, 3 * segment // 2, n))
    seg = np.searchsorted(cuts, t, side="right")
    u = rng.random(seg.max() + 1)[seg]
    return p, float((u < p).mean())


def test_the_interval_holds_its_level_when_neighbouring_frames_err_together() -> None:
    rng = np.random.default_rng(1)
    hits, naive = [], []
    for k in range(200):
        p, truth = correlated_clip(rng, 300, 20)
        s = share_interval(p, 20, 0.9, draws=500, seed=k)
        hits.append(s.low <= truth <= s.high)
        b = share_interval(p, 1, 0.9, draws=500, seed=k)  # frames as independent: binomial-like
        naive.append(b.low <= truth <= b.high)
    assert 0.85 <= np.mean(hits) <= 0.97
    assert np.mean(naive) < 0.6  # what treating frames as independent would claim


def test_a_long_clip_stays_fast() -> None:
    p = np.random.default_rng(2).random(18000)
    s = share_interval(p, block_frames(p, 30.0), 0.9)
    assert s.low < s.value < s.high and s.frames == 18000


def clip_result(tmp_path: Path, frames: int = 90) -> Path:
    doc = result_document(kicking_poses(frames), fps=30.0)
    doc["params"].update({**PARAMS, "temporal": {"mode": "smooth"}})
    return write_document(tmp_path / "clip.zedo.json", doc)


def test_clip_shares_add_up_with_the_frame_rows(tmp_path: Path) -> None:
    a = analyse(read_result(clip_result(tmp_path)), AnalysisSettings(), calibrations=[calibration("smooth", 10.0)])
    clip = {r.measure: r for r in a.rows if r.frame_index is None}
    for name in SYMMETRY_NAMES:
        stem = name.removesuffix("_deg")
        p = [r.value for r in a.rows if r.measure == probability_name(name)]
        assert len(p) == 90 and all(0.0 <= x <= 1.0 for x in p)
        share = clip[f"{stem}_share_asymmetric"]
        assert share.value == pytest.approx(np.mean(p))
        assert share.low <= share.value <= share.high and share.how == SHARE_CALIBRATED
        calls = [r.call for r in a.rows if r.measure == name and r.frame_index is not None]
        fractions = [clip[f"{stem}_fraction_{c}"].value for c in CALLS]
        assert fractions == pytest.approx([calls.count(c) / len(calls) for c in CALLS])  # unchanged
        sure = clip[f"{stem}_fraction_asymmetric"].value  # frames called asymmetric are at least that likely
        assert share.high >= sure
    shank = clip["symmetry_shank_share_asymmetric"]  # the left knee bends 0-60 deg: part of the time above 28
    assert 0.2 < shank.value < 0.8 and shank.high - shank.low > 0.02
    assert clip["symmetry_thigh_share_asymmetric"].value < 0.05  # thighs stay together


def test_without_a_calibration_the_share_says_why(tmp_path: Path) -> None:
    a = analyse(read_result(clip_result(tmp_path, 30)), calibrations=[])
    share = next(r for r in a.rows if r.measure == "symmetry_shank_share_asymmetric")
    assert np.isnan(share.value) and share.how == "none: no frame has a calibrated value"
    assert all(np.isnan(r.value) for r in a.rows if r.measure == probability_name("symmetry_shank_deg"))


def _margin(pair: str, threshold: float, margin: float, level: float = 0.9) -> ShareMargin:
    return ShareMargin(pair=pair, threshold_deg=threshold, level=level, margin=margin, cases=100, sources=["test"],
                       provenance={})  # fmt: skip


def test_a_threshold_between_calibrated_ones_takes_the_larger_margin_and_none_outside() -> None:
    margins = [_margin("symmetry_thigh", 15.0, 0.4), _margin("symmetry_thigh", 28.0, 0.2),
               _margin("symmetry_thigh", 45.0, 0.3)]  # fmt: skip
    assert share_margin(margins, "symmetry_thigh", 28.0, 0.9).margin == 0.2
    assert share_margin(margins, "symmetry_thigh", 20.0, 0.9).margin == 0.4
    assert share_margin(margins, "symmetry_thigh", 30.0, 0.9).margin == 0.3
    assert share_margin(margins, "symmetry_thigh", 50.0, 0.9) is None
    assert share_margin(margins, "symmetry_thigh", 28.0, 0.8) is None  # another level
    assert share_margin(margins, "symmetry_shank", 28.0, 0.9) is None


def test_the_share_interval_holds_the_margin_the_bootstrap_alone_would_not(tmp_path: Path) -> None:
    """A long clip's bootstrap narrows with its length; the share's error on other sources does not, so the interval
    reaches at least the bundled margin either side of the estimate (within [0, 1])."""
    a = analyse(read_result(clip_result(tmp_path, 600)), AnalysisSettings(), calibrations=[calibration("smooth", 10.0)])
    clip = {r.measure: r for r in a.rows if r.frame_index is None}
    for name in SYMMETRY_NAMES:
        stem = name.removesuffix("_deg")
        share = clip[f"{stem}_share_asymmetric"]
        margin = share_margin(bundled_share_margins(), stem, a.settings.threshold_deg, 0.9).margin
        assert share.low <= max(0.0, share.value - margin) + 1e-9
        assert share.high >= min(1.0, share.value + margin) - 1e-9


def test_outside_the_calibrated_thresholds_the_share_has_no_interval(tmp_path: Path) -> None:
    a = analyse(read_result(clip_result(tmp_path)), AnalysisSettings(threshold_deg=60.0),
                calibrations=[calibration("smooth", 10.0)])  # fmt: skip
    share = next(r for r in a.rows if r.measure == "symmetry_shank_share_asymmetric")
    assert np.isfinite(share.value) and np.isnan(share.low) and np.isnan(share.high)
    assert share.how == "none: thresholds 15-45 deg only"


def test_the_bundled_share_margins_cover_every_pair_threshold_and_level() -> None:
    margins = bundled_share_margins()
    for name in SYMMETRY_NAMES:
        for threshold in (15.0, 28.0, 45.0):
            for level in LEVELS:
                held = share_margin(margins, name.removesuffix("_deg"), threshold, level)
                assert held is not None and 0.0 < held.margin < 1.0 and held.cases >= 100


def test_a_long_clips_report_gives_its_shares_minute_by_minute(tmp_path: Path) -> None:
    from zedo_cli.analysis.report.clip_report import epoch_shares, epoch_shares_table

    a = analyse(
        read_result(clip_result(tmp_path, 30 * 150)), AnalysisSettings(), calibrations=[calibration("smooth", 10.0)]
    )
    starts, shares = epoch_shares(a, 0)
    assert starts.tolist() == [0.0, 60.0, 120.0] and shares.shape == (3, 4)
    p = a.probabilities["symmetry_shank_deg"]
    minute = (a.result.frame_index[a.index] // 1800).astype(int)
    assert shares[:, SYMMETRY_NAMES.index("symmetry_shank_deg")] == pytest.approx(
        [np.nanmean(p[minute == m]) for m in range(3)]
    )
    assert "minute by minute" in epoch_shares_table(a, 0) and "2:00" in epoch_shares_table(a, 0)
    short = analyse(
        read_result(clip_result(tmp_path, 90)), AnalysisSettings(), calibrations=[calibration("smooth", 10.0)]
    )
    assert epoch_shares_table(short, 0) == ""
