"""Measure-level calibration: the conformal intervals hold their level on fresh cases,
adapt to the case, shrink where that is more accurate; a calibration is applied only where it
holds, calls are decisive only when the interval says so, and clips keep their summaries true."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from analysis_results import kicking_poses, result_document, write_document

from zedo_cli.analysis.analyse import (
    ANGLE_NAMES,
    FLAG_TOO_FAST,
    SYMMETRY_NAMES,
    AnalysisSettings,
    analyse,
    measure_ranges,
)
from zedo_cli.analysis.pose.symmetry import CALLS
from zedo_cli.analysis.uncertainty.calibration import (
    LEVELS,
    MeasureCalibration,
    MeasureModel,
    find_calibration,
    fit_measure,
    read_calibrations,
    write_calibrations,
)
from zedo_cli.errors import WeightsError
from zedo_cli.formats.readers.result import read_result
from zedo_cli.lifting.config import LiftConfig, calibration_settings

SHA = "ab" * 32
JOINTS = ("right_hip", "right_knee", "right_ankle", "left_hip", "left_knee", "left_ankle", "left_shoulder",
          "left_elbow", "left_wrist", "right_shoulder", "right_elbow", "right_wrist")  # fmt: skip
PARAMS = {"prior": {"sha256": SHA}, "config": LiftConfig().to_dict(), "temporal": {"mode": "none"},
          "camera_sources": ["pseudo"]}  # fmt: skip


def heteroscedastic(n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Measured values and truths: small values are measured well (1 deg noise), large ones badly (15)."""
    rng = np.random.default_rng(seed)
    truth = rng.uniform(0, 90, n)
    noise = np.where(truth < 45, 1.0, 15.0)
    return truth + rng.normal(0, noise), truth


@pytest.mark.parametrize("level", [0.8, 0.9])
def test_intervals_hold_their_level_on_fresh_cases_and_adapt_to_the_case(level: float) -> None:
    value, truth = heteroscedastic(3000, 0)
    model = fit_measure(value, truth, circular=False, bins=2)
    fresh_value, fresh_truth = heteroscedastic(20000, 1)
    est = model.estimate(fresh_value)
    low, high = model.interval(est, fresh_value, level)
    inside = (low <= fresh_truth) & (fresh_truth <= high)
    assert level - 0.02 <= inside.mean() <= level + 0.03
    narrow, wide = (high - low)[fresh_value < 30].mean(), (high - low)[fresh_value > 60].mean()
    assert wide > 2 * narrow  # the well-measured half gets the narrower intervals


def test_shrinkage_is_chosen_when_the_measure_scatters_more_than_the_truth() -> None:
    rng = np.random.default_rng(2)
    truth = rng.normal(30, 5, 4000)
    noisy = fit_measure(truth + rng.normal(0, 15, 4000), truth, circular=False, bins=1)
    exact = fit_measure(truth + rng.normal(0, 0.1, 4000), truth, circular=False, bins=1)
    assert noisy.weight < 0.5 and exact.weight == 1.0
    assert noisy.center == pytest.approx(30, abs=0.5)


def test_circular_measures_shrink_and_err_on_the_circle() -> None:
    model = MeasureModel(175.0, 0.5, (), {0.9: (10.0,)}, {0.9: (10.0,)}, circular=True)
    assert model.estimate(np.array([-175.0]))[0] == pytest.approx(-180.0)  # halfway from 175 to -175 across 180
    truth = np.linspace(150, 210, 7)
    fit = fit_measure(((truth + np.random.default_rng(0).normal(0, 2, 7)) + 180) % 360 - 180,
                      (truth + 180) % 360 - 180, circular=True, bins=1)  # fmt: skip
    assert abs((fit.center - 180 + 180) % 360 - 180) < 5


def calibration(temporal: str = "none", width: float = 5.0, center: float = 20.0) -> MeasureCalibration:
    names = (*SYMMETRY_NAMES, *ANGLE_NAMES)
    q = {lv: (width,) for lv in LEVELS}
    models = {n: MeasureModel(center, 1.0, (), q, q, circular=False) for n in names}
    return MeasureCalibration(SHA, calibration_settings(LiftConfig()), temporal, ("pseudo",), JOINTS, models,
                              {"data": "test"})  # fmt: skip


def test_a_calibration_holds_only_for_its_prior_settings_mode_and_camera(tmp_path: Path) -> None:
    cal = calibration()
    assert find_calibration([cal], PARAMS, JOINTS) == (cal, "calibrated")
    cases = {
        "prior": {**PARAMS, "prior": {"sha256": "cd" * 32}},
        "temporal mode smooth": {**PARAMS, "temporal": {"mode": "smooth"}},
        "lifting settings": {**PARAMS, "config": {**PARAMS["config"], "steps": 7}},
        "camera": {**PARAMS, "camera_sources": ["cli"]},
    }
    for why, params in cases.items():
        found, reason = find_calibration([cal], params, JOINTS)
        assert found is None and why in reason
    assert find_calibration([cal], {}, JOINTS)[0] is None
    path = tmp_path / "m.json"
    write_calibrations(path, [cal])
    assert read_calibrations(path)[0] == cal
    path.write_text('{"format": "zedo.measures", "format_version": 1, "calibrations": [{"prior_sha256": 1}]}')
    with pytest.raises(WeightsError, match="unreadable measure calibration"):
        read_calibrations(path)


def document(poses: np.ndarray, *, fps: float | None = None, temporal: str = "none") -> dict:
    doc = result_document(poses, fps=fps)
    doc["params"].update({**PARAMS, "temporal": {"mode": temporal}, "fps": fps})
    return doc


def test_calibrated_rows_give_intervals_and_selective_calls(tmp_path: Path) -> None:
    poses = kicking_poses(30)
    path = write_document(tmp_path / "k.zedo.json", document(poses))
    a = analyse(read_result(path), AnalysisSettings(), calibrations=[calibration(width=5.0)])
    assert a.uncertainty_available
    shank = [r for r in a.rows if r.measure == "symmetry_shank_deg"]
    for r in shank:  # interval = value +- 5 (clipped at 0); the call follows the interval
        assert r.how == "calibrated"
        assert r.low == pytest.approx(max(r.value - 5, 0)) and r.high == pytest.approx(r.value + 5)
        expected = "symmetric" if r.value + 5 <= 28 else "asymmetric" if r.value - 5 > 28 else "uncertain"
        assert r.call == expected
    assert {r.call for r in shank} == set(CALLS)  # 0-60 degrees of knee bend crosses the threshold


def test_a_bin_fitted_on_too_few_cases_gives_no_interval_and_says_so(tmp_path: Path) -> None:
    # 5 cases per bin cannot back a 90 % interval: the fit stores none, the file keeps none, and a pose in that
    # bin gets no interval with the reason, never an infinite one and never the largest residual
    rng = np.random.default_rng(0)
    fitted = fit_measure(rng.uniform(0, 60, 5), rng.uniform(0, 60, 5), circular=False, bins=1)
    assert np.isnan(fitted.q_high[0.9][0]) and np.isnan(fitted.q_low[0.9][0])
    assert np.isfinite(fitted.q_high[0.5][0])  # a 50 % quantile exists with 5 cases
    cal = calibration()
    sparse = {n: MeasureModel(20.0, 1.0, (), {lv: (np.nan,) for lv in LEVELS}, {lv: (np.nan,) for lv in LEVELS},
                              circular=False) for n in cal.measures}  # fmt: skip
    cal = MeasureCalibration(cal.prior_sha256, cal.settings, "none", ("pseudo",), JOINTS, sparse, {"data": "test"})
    path = tmp_path / "m.json"
    write_calibrations(path, [cal])
    assert np.isnan(read_calibrations(path)[0].measures["symmetry_shank_deg"].q_high[0.9][0])
    doc = write_document(tmp_path / "k.zedo.json", document(kicking_poses(10)))
    a = analyse(read_result(doc), AnalysisSettings(), calibrations=read_calibrations(path))
    shank = [r for r in a.rows if r.measure == "symmetry_shank_deg"]
    assert shank and all(r.how == "none: too few calibration cases" for r in shank)
    assert all(np.isnan(r.low) and np.isnan(r.high) and r.call == "uncertain" for r in shank)


def test_without_a_matching_calibration_every_call_is_uncertain_and_says_why(tmp_path: Path) -> None:
    path = write_document(tmp_path / "k.zedo.json", document(kicking_poses(10), temporal="two-pass"))
    a = analyse(read_result(path), calibrations=[calibration()])
    frame_rows = [
        r for r in a.rows if r.frame_index is not None and r.unit == "deg" and not r.measure.startswith("head_")
    ]
    assert all(np.isnan(r.low) for r in frame_rows)
    assert {r.how for r in frame_rows} == {"none: no measure calibration for temporal mode two-pass"}
    assert {r.call for r in frame_rows if r.measure in SYMMETRY_NAMES} == {"uncertain"}


def test_a_joint_filled_by_the_prior_gets_no_interval(tmp_path: Path) -> None:
    doc = document(kicking_poses(3))
    doc["frames"][0]["persons"][0]["observed"][JOINTS.index("left_wrist")] = False
    a = analyse(read_result(write_document(tmp_path / "k.zedo.json", doc)), calibrations=[calibration()])
    forearm = [r for r in a.rows if r.measure == "symmetry_forearm_deg"]
    assert forearm[0].how == "none: joint filled by the prior (not calibrated): left_wrist"
    assert forearm[0].call == "uncertain" and np.isnan(forearm[0].low)
    assert forearm[1].how == "calibrated"
    elbow = [r for r in a.rows if r.measure == "left_elbow_flexion_deg"][0]
    assert elbow.how.startswith("none: joint filled")


def test_clip_summaries_agree_with_the_frames_and_fast_glitches_are_kept_out(tmp_path: Path) -> None:
    poses = kicking_poses(60)
    glitch = poses[30].copy()
    glitch[JOINTS.index("left_ankle")] = glitch[JOINTS.index("left_knee")] + [0.0, -0.1, 0.0]  # knee folds at once
    poses[30] = glitch
    path = write_document(tmp_path / "k.zedo.json", document(poses, fps=30.0, temporal="smooth"))
    a = analyse(read_result(path), AnalysisSettings(), calibrations=[calibration("smooth")])
    knee = [r for r in a.rows if r.measure == "left_knee_flexion_deg"]
    assert [r.frame_index for r in knee if r.flag == FLAG_TOO_FAST] == [30, 31]  # into and out of the glitch
    clip = {r.measure: r for r in a.rows if r.frame_index is None}
    assert clip["left_knee_flexion_frames_too_fast"].value == 2
    assert clip["left_knee_flexion_range_deg"].value == pytest.approx(60.0, abs=0.5)  # the glitch is not in it
    for name in SYMMETRY_NAMES:
        stem = name.removesuffix("_deg")
        calls = [r.call for r in a.rows if r.measure == name and r.frame_index is not None]
        shares = [clip[f"{stem}_fraction_{c}"].value for c in CALLS]
        assert shares == pytest.approx([calls.count(c) / len(calls) for c in CALLS])
        values = [r.value for r in a.rows if r.measure == name and r.frame_index is not None]
        assert clip[f"{stem}_median_deg"].value == pytest.approx(np.median(values))
        assert clip[f"{stem}_median_deg"].how == "median_of_frame_interval_ends"


def test_every_angle_stays_in_its_stated_range() -> None:
    rng = np.random.default_rng(0)
    poses = rng.normal(0, 0.15, (3000, 12, 3))
    from analysis_poses import SKEL

    from zedo_cli.analysis.analyse import all_measures

    ranges = measure_ranges()
    for name, v in all_measures(poses, SKEL).items():
        lo, hi = ranges[name]
        known = v[np.isfinite(v)]
        assert ((known >= lo) & (known <= hi)).all(), name


def test_each_interval_names_the_calibration_that_backs_it(tmp_path: Path) -> None:
    from zedo_cli.analysis.outputs import analysis_document
    from zedo_cli.analysis.uncertainty.calibration import calibration_id

    cal = calibration(width=5.0)
    a = analyse(read_result(write_document(tmp_path / "k.zedo.json", document(kicking_poses(30)))),
                AnalysisSettings(), calibrations=[cal])  # fmt: skip
    doc = analysis_document(a)
    (used,) = doc["uncertainty"]["calibrations"]
    assert used["id"] == calibration_id(cal) and len(used["id"]) == 16
    assert (used["scope"], used["temporal_mode"], used["cameras"], used["data"]) == (
        "frames",
        "none",
        ["pseudo"],
        "test",
    )
    assert any(n.startswith(f"frames intervals backed by measure calibration {used['id']}") for n in a.notes)
    assert calibration_id(calibration(width=6.0)) != used["id"]  # another calibration, another id
    none = analyse(read_result(write_document(tmp_path / "n.zedo.json", document(kicking_poses(30)))),
                   AnalysisSettings(), calibrations=[])  # fmt: skip
    assert analysis_document(none)["uncertainty"]["calibrations"] == []


def test_a_clip_filmed_upside_down_is_outside_calibration_and_says_so(tmp_path: Path) -> None:
    poses = kicking_poses(60)
    upright = analyse(read_result(write_document(tmp_path / "up.zedo.json", document(poses, fps=30.0))),
                      AnalysisSettings(), calibrations=[calibration()])  # fmt: skip
    assert {r.how for r in upright.rows if r.measure == "symmetry_thigh_deg"} == {"calibrated"}
    turned = poses * np.array([-1.0, -1.0, 1.0])  # the camera turned half a turn about its axis: head down the image
    doc = document(turned, fps=30.0)
    a = analyse(read_result(write_document(tmp_path / "down.zedo.json", doc)), AnalysisSettings(),
                calibrations=[calibration()])  # fmt: skip
    frames = {r.how for r in a.rows if r.measure == "symmetry_thigh_deg"}
    (why,) = frames
    assert why.startswith("none: outside calibration: the infant's trunk points 1") and "turn the video" in why
    assert not a.uncertainty_available and all(np.isnan(r.low) for r in a.rows if r.measure == "symmetry_thigh_deg")
    shares = [r for r in a.rows if r.measure.endswith("_share_asymmetric")]
    assert shares and all(np.isnan(r.low) for r in shares)
