"""Clip-scope measure calibrations of the `3d_` clip features: a calibrated feature
gets a shrinkage estimate and its interval, an uncalibrated one the reason; clip calibrations leave the
frame measures alone."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from analysis_results import kicking_poses, write_document
from test_calibration import JOINTS, PARAMS, SHA, calibration, document

from zedo_cli.analysis.analyse import AnalysisSettings, analyse
from zedo_cli.analysis.clip.clip_features import feature_range
from zedo_cli.analysis.uncertainty.calibration import (
    LEVELS,
    CameraDomain,
    MeasureCalibration,
    MeasureModel,
    assign_calibrations,
    clip_camera_mismatch,
    find_calibration,
    held_out_note,
    read_calibrations,
    write_calibrations,
)
from zedo_cli.formats.readers.result import read_result
from zedo_cli.lifting.config import LiftConfig, calibration_settings

KNEE = "3d_mean_angle_RKnee"


def clip_calibration(temporal: str = "smooth", width: float = 4.0, weight: float = 0.5) -> MeasureCalibration:
    q = {lv: (width, 2 * width) for lv in LEVELS}  # two bins of the measured value, split at 100 degrees
    models = {KNEE: MeasureModel(120.0, weight, (100.0,), q, q, circular=False)}
    return MeasureCalibration(SHA, calibration_settings(LiftConfig()), temporal, ("pseudo",), JOINTS, models,
                              {"data": "test", "fps": 30.0}, scope="clips")  # fmt: skip


def clip_rows(tmp_path: Path, calibrations: list[MeasureCalibration], temporal: str = "smooth") -> dict:
    doc = document(kicking_poses(90), fps=30.0, temporal=temporal)
    a = analyse(read_result(write_document(tmp_path / "k.zedo.json", doc)), AnalysisSettings(),
                calibrations=calibrations)  # fmt: skip
    return {r.measure: r for r in a.rows if r.frame_index is None}


def test_a_calibrated_3d_feature_gets_its_estimate_and_interval(tmp_path: Path) -> None:
    rows = clip_rows(tmp_path, [calibration("smooth"), clip_calibration()])
    knee = rows[KNEE]
    assert knee.how == "calibrated"
    raw = knee.raw_value
    assert raw == pytest.approx(180.0, abs=1e-3)  # a straight leg
    assert knee.value == pytest.approx(120.0 + 0.5 * (raw - 120.0))  # shrunk half-way to the centre
    assert (knee.low, knee.high) == pytest.approx((knee.value - 8.0, knee.value + 8.0))  # the upper bin's
    # a feature the calibration has no model of says so; the published 2D ones stay uncalibrated
    assert rows["3d_mean_angle_LElbow"].how == "none: the measure calibration has no 3d_mean_angle_LElbow"
    assert np.isnan(rows["3d_mean_angle_LElbow"].low) and np.isnan(rows["3d_mean_angle_LElbow"].raw_value)
    assert rows["mean_angle_RKnee"].how == "none: published 2D feature"


def test_intervals_stay_in_the_features_range(tmp_path: Path) -> None:
    rows = clip_rows(tmp_path, [clip_calibration(width=30.0, weight=1.0)])
    assert rows[KNEE].high == 180.0 and rows[KNEE].low == pytest.approx(rows[KNEE].value - 60.0)
    assert feature_range("3d_lrCorr_angle_Knee") == (-1.0, 1.0)
    assert feature_range("3d_mean_angle_LHipFlexion") == (-90.0, 270.0)
    assert feature_range("3d_median_vel_angle_LKnee") == (0.0, np.inf)


def test_an_uncalibrated_3d_feature_gets_the_reason(tmp_path: Path) -> None:
    none = clip_rows(tmp_path, [calibration("smooth")])  # only frame calibrations
    assert none[KNEE].how == "none: no measure calibration installed" and np.isnan(none[KNEE].low)
    other_mode = clip_rows(tmp_path, [clip_calibration("none")])  # calibrated on smooth lifts only
    assert other_mode[KNEE].how == "none: no measure calibration for temporal mode smooth"
    assert np.isnan(other_mode[KNEE].high) and np.isfinite(other_mode[KNEE].value)


def test_clip_calibrations_leave_frame_measures_alone(tmp_path: Path) -> None:
    frames = calibration("smooth")
    clips = clip_calibration()
    params = {**PARAMS, "temporal": {"mode": "smooth"}}
    assert find_calibration([clips, frames], params, JOINTS) == (frames, "calibrated")
    assert find_calibration([clips, frames], params, JOINTS, scope="clips") == (clips, "calibrated")
    got = assign_calibrations([clips, frames], params, JOINTS, np.full(2, np.nan), np.full(2, np.nan))
    assert got.calibrations == (frames,) and (got.index == 0).all()
    path = tmp_path / "m.json"
    write_calibrations(path, [frames, clips])
    assert read_calibrations(path) == [frames, clips]
    assert path.read_text().count('"scope"') == 1  # a frame calibration's entry reads and writes as before


def known_cameras(depth_m: tuple[float, float] = (0.5, 1.5)) -> MeasureCalibration:
    """The test clip calibration made over known cameras: f = 900-1100 px, the infant `depth_m` away."""
    return replace(clip_calibration(), cameras=("cli", "file"), domain=CameraDomain(depth_m, (900.0, 1100.0)))


def camera_clip_rows(tmp_path: Path, calibrations: list[MeasureCalibration], shift_m: float = 0.0,
                     sources: tuple[str, ...] = ("cli",)) -> dict:  # fmt: skip
    """The clip rows of a kicking clip 1 m (+ `shift_m`) from a camera of f = 1000 px given with --focal."""
    doc = document(kicking_poses(90) + np.array([0.0, 0.0, shift_m]), fps=30.0, temporal="smooth")
    doc["params"]["camera_sources"] = list(sources)
    a = analyse(read_result(write_document(tmp_path / "k.zedo.json", doc)), AnalysisSettings(),
                calibrations=calibrations)  # fmt: skip
    return {r.measure: r for r in a.rows if r.frame_index is None}


def test_a_clip_calibration_of_known_cameras_holds_for_clips_inside_its_range(tmp_path: Path) -> None:
    """A clip lifted with --focal gets the known cameras' clip calibration where its median root depth and
    focal length lie in the calibration's domain; outside it the pseudo camera's clip calibration stands in where
    there is one, else the reason with the clip's camera."""
    inside = camera_clip_rows(tmp_path, [clip_calibration(), known_cameras()])
    assert inside[KNEE].how == "calibrated" and np.isfinite(inside[KNEE].low)
    stood_in = camera_clip_rows(tmp_path, [clip_calibration(), known_cameras()], shift_m=2.0)
    assert stood_in[KNEE].how == "calibrated" and np.isfinite(stood_in[KNEE].low)
    far = camera_clip_rows(tmp_path, [known_cameras()], shift_m=2.0)
    assert far[KNEE].how == (
        "none: camera outside the calibrated range (the clip's median root depth 3.00 m, "
        "focal length 1000 px; calibrated: root depth 0.5-1.5 m, focal length 900-1100 px)"
    )
    assert np.isnan(far[KNEE].low) and far[KNEE].value == pytest.approx(180.0, abs=1e-3)  # the raw feature
    only_pseudo = camera_clip_rows(tmp_path, [clip_calibration()])
    assert only_pseudo[KNEE].how == "none: no measure calibration for this camera (calibrated: pseudo)"
    pseudo_result = camera_clip_rows(tmp_path, [known_cameras()], sources=("pseudo",))
    assert pseudo_result[KNEE].how == "none: no measure calibration for this camera (calibrated: cli, file)"


def test_a_clip_whose_camera_cannot_be_checked_gets_no_known_camera_interval() -> None:
    cal = known_cameras()
    assert clip_camera_mismatch(cal, np.array([0.9, 1.0, np.nan, 1.2]), np.full(4, 1000.0)) is None  # median 1.0
    assert "the clip's median root depth 1.60 m" in clip_camera_mismatch(
        cal, np.array([1.0, 1.6, 1.7]), np.full(3, 1e3)
    )
    assert "cannot be checked" in clip_camera_mismatch(cal, np.full(3, np.nan), np.full(3, 1000.0))
    assert clip_camera_mismatch(clip_calibration(), np.full(3, np.nan), np.full(3, np.nan)) is None  # no domain


def test_the_bundled_clip_calibrations_cover_every_mode_and_both_kinds_of_camera() -> None:
    """A clip lifted frame by frame (zedo lift's default), with --temporal smooth or as one infant (clip), by the
    pseudo camera or a known one up to 3.5 m and 3000 px, finds a clip calibration with every 3d_ feature's model,
    fitted on held-out clips of two sources, with its cross-fitted and its held-out-by-source coverage stated
    (docs/movement.md)."""
    from zedo_cli.analysis.clip.features_3d import features_3d
    from zedo_cli.analysis.uncertainty.calibration import bundled_calibrations
    from zedo_cli.data.skeleton import get_skeleton
    from zedo_cli.lifting.config import DEFAULT_PRESET, get_preset

    clips = [c for c in bundled_calibrations() if c.scope == "clips"]
    names = set(features_3d(kicking_poses(60) - np.array([0.0, 0.0, 1.0]), get_skeleton("syrip12"), 30.0).values)
    for mode in ("none", "smooth", "clip"):
        for sources in (["pseudo"], ["cli"], ["file"]):
            params = {"prior": {"sha256": clips[0].prior_sha256}, "config": get_preset(DEFAULT_PRESET).to_dict(),
                      "temporal": {"mode": mode}, "camera_sources": sources}  # fmt: skip
            found, why = find_calibration(clips, params, clips[0].joints, scope="clips")
            assert why == "calibrated" and found is not None and found.temporal_mode == mode
            assert (found.domain is None) == (sources == ["pseudo"]) and set(found.measures) == names
            if found.domain is not None:
                assert found.domain.contains(np.array([3.4]), np.array([2990.0]))[0]
            assert 0.85 <= np.mean(list(found.provenance["cross_fitted_coverage_90"].values())) <= 0.95
            assert set(found.provenance["held_out_by_source_coverage_90"]) == {"SyRIP poses", "adult motion"}
    assert len(clips) == 6  # one per mode and kind of camera


def test_a_clip_outside_calibration_states_no_3d_interval_and_says_why(tmp_path: Path) -> None:
    doc = document(kicking_poses(90) * np.array([-1.0, -1.0, 1.0]), fps=30.0, temporal="smooth")  # head down
    a = analyse(read_result(write_document(tmp_path / "down.zedo.json", doc)), AnalysisSettings(),
                calibrations=[calibration("smooth"), clip_calibration()])  # fmt: skip
    knee = next(r for r in a.rows if r.frame_index is None and r.measure == KNEE)
    assert knee.how.startswith("none: outside calibration: the infant's trunk points")
    assert np.isnan(knee.low) and knee.value == pytest.approx(180.0, abs=1e-3)  # the measurement, unshrunk


def test_the_analysis_says_how_the_clip_calibration_held_on_sources_left_out(tmp_path: Path) -> None:
    one_source = clip_calibration()
    checked = replace(one_source, provenance={**one_source.provenance, "held_out_by_source_coverage_90": {
        "adult motion": {"mean_angle": 0.7, "all": 0.8}, "SyRIP poses": {"mean_angle": 0.9, "all": 0.91}}})  # fmt: skip
    doc = document(kicking_poses(90), fps=30.0, temporal="smooth")
    a = analyse(read_result(write_document(tmp_path / "k.zedo.json", doc)),
                AnalysisSettings(), calibrations=[calibration("smooth"), checked])  # fmt: skip
    note = next(n for n in a.notes if "by a fit on the others" in n)
    assert "91 % (SyRIP poses), 80 % (adult motion) of cases" in note and "approximate" in note  # 80 % < 85 %
    assert "one clip source" in held_out_note(one_source)
    # the frame calibration of this analysis, checked on no other source, says so too
    assert any(n.startswith("the frame measures' intervals were fitted on one clip source") for n in a.notes)
    frames = replace(calibration("smooth"), provenance={"held_out_by_source_coverage_90": {"a": {"all": 0.6}}})
    assert held_out_note(frames).startswith("the frame measures' intervals were fitted on lifts of 1 source;")
    fine = replace(checked, provenance={"held_out_by_source_coverage_90": {"a": {"all": 0.86}, "b": {"all": 0.9}}})
    assert "approximate" not in held_out_note(fine)
