"""The calibration of the head's clip intervals: the bundled file is read and matches the default
settings, its factor widens the bootstrap's arms, other settings get no interval, a malformed file
is one line, and the conformal quantile covers what it says."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from zedo_cli.analysis.pose.head import TURN_CALLS, HeadFrames, HeadSettings, head_clip, head_clip_bootstrap
from zedo_cli.analysis.uncertainty.block_bootstrap import BootstrapSettings
from zedo_cli.analysis.uncertainty.calibration import LEVELS
from zedo_cli.analysis.uncertainty.head_calibration import (
    MEASURES,
    HeadCalibration,
    HeadMeasureCalibration,
    MeasureFactor,
    bundled_head_calibrations,
    bundled_path,
    conformal_factor,
    find_head_calibration,
    head_settings_key,
    read_head_calibrations,
    scores,
    write_head_calibrations,
)
from zedo_cli.errors import WeightsError


def _frames(seconds: float = 120.0, fps: float = 30.0, seed: int = 3) -> HeadFrames:
    """A track of holds of about 2 s at left / right / midline, a tilt wandering about 4 degrees."""
    rng = np.random.default_rng(seed)
    n = int(seconds * fps)
    holds = np.repeat(rng.choice(np.array(TURN_CALLS, dtype=object), n // 60 + 1, p=[0.4, 0.3, 0.3]), 60)[:n]
    holds[rng.random(n) < 0.05] = ""  # frames without a call
    tilt = 4.0 + np.cumsum(rng.normal(0, 0.3, n)) * 0.1 + rng.normal(0, 1.0, n)
    empty = np.full(n, "", dtype=object)
    return HeadFrames(tilt, empty, empty, np.full(n, np.nan), holds, empty)


def _default_key() -> dict:
    s = HeadSettings()
    return head_settings_key(s.midline_deg, s.model, s.bootstrap)


def test_the_bundled_calibration_is_read_and_fits_the_default_settings() -> None:
    assert bundled_path().exists()
    cal = find_head_calibration(bundled_head_calibrations(), _default_key())
    assert cal is not None
    for m in MEASURES:
        assert set(cal.measures[m].levels) == set(LEVELS)  # every --level of zedo analyze
        assert 0 < cal.measures[m].error < (0.1 if m.startswith("head_turn") else 2.0)
        f = cal.measures[m].levels[0.9]
        assert f.factor > 0 and f.calibration_clips >= 100 and f.held_out_clips >= 100
        assert 0.85 <= f.held_out_coverage <= 0.95, (m, f)  # what the benchmark measured on held-out clips
        factors = [cal.measures[m].levels[level].factor for level in LEVELS]
        assert factors == sorted(factors)  # a higher level, a wider interval
    assert "head_measures.py" in cal.provenance and "--write" in cal.provenance


def test_the_calibration_widens_the_bootstrap_arms_by_its_factor() -> None:
    h = _frames()
    frames = np.arange(len(h.tilt_deg))
    raw = head_clip_bootstrap(frames, h, 30.0)
    cal = find_head_calibration(bundled_head_calibrations(), _default_key())
    assert cal is not None
    for r, c in zip(raw, head_clip(frames, h, 30.0), strict=True):
        m = cal.measures[r.measure]
        f, e = m.levels[0.9].factor, m.error
        lo, hi = (-90.0, 90.0) if r.measure == "head_tilt_median_deg" else (0.0, 1.0)
        assert c.value == r.value and np.isfinite(r.interval.low)
        assert c.interval.low == pytest.approx(max(lo, r.value - f * np.hypot(r.value - r.interval.low, e)))
        assert c.interval.high == pytest.approx(min(hi, r.value + f * np.hypot(r.interval.high - r.value, e)))
        assert c.interval.high - c.interval.low > r.interval.high - r.interval.low
        assert c.interval.how.startswith("calibrated: circular block bootstrap") and f"x{f:.2f}" in c.interval.how
        assert f"{m.levels[0.9].held_out_coverage:.1%}" in c.interval.how and f"error of {e:.3g}" in c.interval.how
    # a calibration of its own, no measurement error and factor 2 at 80 %: the arms twice the bootstrap's
    doubled = dataclasses.replace(cal, measures={
        k: HeadMeasureCalibration(0.0, {0.8: dataclasses.replace(m.levels[0.9], factor=2.0)})
        for k, m in cal.measures.items()})  # fmt: skip
    tilt_raw, tilt = raw[3], head_clip(frames, h, 30.0, calibrations=[doubled], level=0.8)[3]
    assert tilt.interval.high - tilt.interval.low == pytest.approx(
        2.0 * (tilt_raw.interval.high - tilt_raw.interval.low)
    )
    assert "for 80%" in tilt.interval.how
    missing = head_clip(frames, h, 30.0, calibrations=[doubled])[3]  # no factor at 90 %
    assert np.isnan(missing.interval.low) and "at 90%" in missing.interval.how
    narrow, wide = (head_clip(frames, h, 30.0, level=lv)[0].interval for lv in (0.5, 0.95))
    assert wide.low < narrow.low < narrow.high < wide.high


def test_other_settings_get_no_interval() -> None:
    h = _frames(60.0)
    frames = np.arange(len(h.tilt_deg))
    for settings in (HeadSettings(midline_deg=25.0), HeadSettings(bootstrap=BootstrapSettings(replicates=500))):
        for stat in head_clip(frames, h, 30.0, settings):
            assert np.isfinite(stat.value) and np.isnan(stat.interval.low) and np.isnan(stat.interval.high)
            assert stat.interval.how.startswith("none: no calibration of the head intervals for these settings")
    seeded = head_clip(frames, h, 30.0, HeadSettings(bootstrap=BootstrapSettings(seed=5)))  # the seed is not matched
    assert all(s.interval.how.startswith("calibrated") for s in seeded)
    assert all(np.isnan(s.interval.low) for s in head_clip(frames, h, 30.0, calibrations=[]))


def test_a_calibration_file_round_trips_and_a_malformed_one_is_one_line(tmp_path: Path) -> None:
    levels = {0.9: MeasureFactor(1.25, 300, 0.9, 300), 0.5: MeasureFactor(0.6, 300, 0.51, 300)}
    cal = HeadCalibration(_default_key(), {m: HeadMeasureCalibration(0.02, levels) for m in MEASURES}, "a test")
    path = tmp_path / "head.json"
    write_head_calibrations(path, [cal])
    assert read_head_calibrations(path) == [cal]
    doc = json.loads(path.read_text())

    def measures(d: dict) -> dict:
        return d["calibrations"][0]["measures"]

    bad = {
        "negative factor": lambda d: measures(d)["head_tilt_median_deg"]["levels"]["0.9"].update(factor=-1),
        "negative error": lambda d: measures(d)["head_turn_fraction_left"].update(error=-0.1),
        "missing measure": lambda d: measures(d).pop("head_turn_fraction_left"),
        "coverage out of range": lambda d: measures(d)["head_turn_fraction_right"]["levels"]["0.5"].update(
            held_out_coverage=90.0),
        "level out of range": lambda d: measures(d)["head_turn_fraction_midline"]["levels"].update(
            {"90": {"factor": 1.0, "calibration_clips": 1, "held_out_coverage": 0.9, "held_out_clips": 1}}),
        "no levels": lambda d: measures(d)["head_turn_fraction_midline"].update(levels={}),
        "no settings": lambda d: d["calibrations"][0].pop("settings"),
        "not a list": lambda d: d.update(calibrations={}),
    }  # fmt: skip
    for why, spoil in bad.items():
        d = json.loads(json.dumps(doc))
        spoil(d)
        path.write_text(json.dumps(d))
        with pytest.raises(WeightsError, match=r"head\.json: unreadable head interval calibration") as err:
            read_head_calibrations(path)
        assert "\n" not in str(err.value), why
    path.write_text(json.dumps({**doc, "format_version": 2}))
    with pytest.raises(WeightsError, match="not a zedo.head_intervals version 1 file"):
        read_head_calibrations(path)
    path.write_text("{")
    with pytest.raises(WeightsError, match="unreadable head interval calibration"):
        read_head_calibrations(path)


def test_scores_and_the_conformal_quantile() -> None:
    est, low, high = np.full(4, 0.5), np.full(4, 0.4), np.full(4, 0.7)
    s = scores(est, low, high, np.array([0.5, 0.3, 0.8, 0.65]), 0.0)
    assert s == pytest.approx([0.0, 2.0, 1.5, 0.75])  # the arm on the truth's side: 0.1 below, 0.2 above
    assert scores(est, low, high, np.array([0.3]), 0.1)[0] == pytest.approx(0.2 / np.hypot(0.1, 0.1))
    assert scores(np.array([0.0]), np.array([0.0]), np.array([0.1]), np.array([-0.1]), 0.0)[0] == np.inf
    assert conformal_factor(np.arange(1.0, 10.0), 0.9) == 9.0  # ceil(10 * 0.9) = 9th of 9
    assert np.isnan(conformal_factor(np.arange(1.0, 8.0), 0.9))  # too few for 90 %: none, not infinity
    rng = np.random.default_rng(0)
    hits = []  # the quantile of 49 scores covers 45 / 50 of new ones on average
    for _ in range(400):
        cal, new = rng.exponential(size=49), rng.exponential()
        hits.append(new <= conformal_factor(cal, 0.9))
    assert 0.86 <= np.mean(hits) <= 0.95


def test_zedo_analyze_gives_the_head_intervals_at_its_level(tmp_path: Path) -> None:
    from test_head import _result_with_faces

    from zedo_cli.analysis.analyse import AnalysisSettings, analyse
    from zedo_cli.formats.readers.result import read_result

    yaws = np.concatenate([np.zeros(60), np.full(90, -50.0), np.linspace(-50, 50, 30), np.full(60, 45.0)])
    res = read_result(_result_with_faces(tmp_path, yaws))
    rows = {}
    for level in (0.9, 0.95):
        a = analyse(res, AnalysisSettings(level=level))
        rows[level] = {r.measure: r for r in a.rows if r.frame_index is None and r.measure.startswith("head_")}
    for measure in MEASURES:
        at90, at95 = rows[0.9][measure], rows[0.95][measure]
        assert at90.value == at95.value
        assert at90.how.startswith("calibrated") and "for 90%" in at90.how and "for 95%" in at95.how
        assert at95.low <= at90.low <= at90.value <= at90.high <= at95.high
