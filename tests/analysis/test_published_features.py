"""The published 2D clip features (Chambers et al. 2020) and the 3d_ features: names, angle conventions,
the body frame and the quirks kept, short clips and missing joints, and their rows in `zedo analyze`.
(The comparison with the published code itself: test_published_features_oracle.py.)"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from analysis_poses import SKEL, rotation, set_limb, standing, to_array
from analysis_results import kicking_poses, result_document, write_document

from zedo_cli.analysis.analyse import AnalysisSettings, analyse
from zedo_cli.analysis.clip.features_3d import features_3d
from zedo_cli.analysis.clip.published_features import (
    ANGLE_POINTS,
    POINTS,
    PREREGISTERED,
    body_frame,
    published_features,
)
from zedo_cli.analysis.outputs import csv_text
from zedo_cli.formats.readers.result import read_result

# A still infant on its back seen from above, its head up in the image and its left on the image's right:
# upper arms along the trunk with the forearms out (elbows at 90 degrees), legs straight, in pixels.
STILL = {
    "left_shoulder": (700, 200), "right_shoulder": (580, 200), "left_hip": (680, 350), "right_hip": (600, 350),
    "left_elbow": (700, 280), "right_elbow": (580, 280), "left_wrist": (780, 280), "right_wrist": (500, 280),
    "left_knee": (680, 450), "right_knee": (600, 450), "left_ankle": (680, 550), "right_ankle": (600, 550),
}  # fmt: skip
SIZE = np.array([1280.0, 720.0])


def still_clip(frames: int = 90, turn_deg: float = 0.0, scale: float = 1.0, shift: float = 0.0) -> np.ndarray:
    """`(T, 12, 2)` pixels of STILL with 0.05 px of noise, turned in the image about its centre, scaled, moved."""
    xy = np.array([STILL[j] for j in SKEL.joints], dtype=float)[None]  # (1, 12, 2)
    xy = xy + np.random.default_rng(0).normal(0, 0.05, (frames, 12, 2))  # (T, 12, 2)
    c, s = np.cos(np.radians(turn_deg)), np.sin(np.radians(turn_deg))
    return (xy - SIZE / 2) @ np.array([[c, s], [-s, c]]) * scale + SIZE / 2 + shift


def test_names_are_the_published_ones() -> None:
    f = published_features(still_clip(), SKEL, 30.0, SIZE)
    per_side = 8 * 6 + 4 + 4 * 11 + 6  # angle stats, angle correlations, xy stats, distance correlations
    assert len(f.values) == per_side + 38 and len(PREREGISTERED) == 38
    for name in ("medianx_LAnkle", "IQR_vel_angle_RKnee", "lrCorr_angle_Knee", "lrCorr_x_Wrist", "meanent_RWrist",
                 "stdev_angle_LShoulder", "Ankle_medianx", "Knee_lrCorr_angle", "Elbow_entropy_angle"):  # fmt: skip
        assert name in f.values
    assert set(PREREGISTERED) <= set(f.values) and f.units["mean_angle_LElbow"] == "deg"
    assert set(POINTS) - {"Neck"} == set(ANGLE_POINTS) | {"LWrist", "RWrist", "LAnkle", "RAnkle"}


def test_angle_conventions() -> None:
    v = published_features(still_clip(), SKEL, 30.0, SIZE).values
    for side in "LR":
        assert v[f"mean_angle_{side}Elbow"] == pytest.approx(90.0, abs=0.1)  # at the elbow, shoulder to wrist
        assert v[f"mean_angle_{side}Knee"] == pytest.approx(180.0, abs=0.1)  # straight
        assert v[f"mean_angle_{side}Shoulder"] == pytest.approx(90.0, abs=0.1)  # the arm along the trunk, both sides
        assert v[f"mean_angle_{side}Hip"] == pytest.approx(90.0, abs=0.1)
    raised = still_clip()
    raised[:, SKEL.index("right_elbow"), 1] = 120.0  # the right upper arm up beside the head: 270 degrees,
    # whose circular mean the published code reports in (-180, 180]
    assert published_features(raised, SKEL, 30.0, SIZE).values["mean_angle_RShoulder"] == pytest.approx(-90, abs=0.1)


def test_body_frame_is_free_of_image_position_size_and_turn() -> None:
    base = published_features(still_clip(), SKEL, 30.0, SIZE).values
    # trunk 150 px: the left ankle 40 px right of the hips' midpoint and 200 px below it, lower body + 1
    assert base["medianx_LAnkle"] == pytest.approx(40 / 150, abs=1e-3)
    assert base["mediany_LAnkle"] == pytest.approx(200 / 150 + 1, abs=1e-3)
    assert base["medianx_RWrist"] == pytest.approx(-140 / 150, abs=1e-3)
    assert base["mediany_RWrist"] == pytest.approx(80 / 150, abs=1e-3)
    moved = published_features(still_clip(scale=0.5, shift=40.0), SKEL, 30.0, 2 * SIZE).values
    for name, value in base.items():
        assert moved[name] == pytest.approx(value, rel=1e-9, abs=1e-9, nan_ok=True), name
    # turned in the image: the same up to the per-coordinate median of the published smoothing
    for turn in (30.0, 160.0, -75.0):
        turned = published_features(still_clip(turn_deg=turn), SKEL, 30.0, SIZE).values
        for name in ("medianx_LAnkle", "mediany_RWrist", "mean_angle_LElbow", "Knee_mean_angle"):
            assert turned[name] == pytest.approx(base[name], abs=0.02), (turn, name)


def test_hip_line_angle_is_matched_to_the_shoulders_by_position_as_published() -> None:
    t = 6
    x, y = np.zeros((t, len(POINTS))), np.zeros((t, len(POINTS)))
    at = {p: i for i, p in enumerate(POINTS)}
    x[:, at["LShoulder"]], x[:, at["RShoulder"]] = 1.0, -1.0
    tilt = np.radians(10.0 * np.arange(t))  # the hip line turns 10 degrees a frame
    for p, s in (("LHip", 1.0), ("RHip", -1.0)):
        x[:, at[p]], y[:, at[p]] = s * np.cos(tilt), 2.0 + s * np.sin(tilt)
    xb, yb = body_frame(x, y)
    np.testing.assert_allclose(yb[:, at["LHip"]], yb[:, at["RHip"]], atol=1e-12)  # by frame: hips level
    x[:2, [at["LHip"], at["RHip"]]] = np.nan  # the hips seen from frame 2 only
    y[:2, [at["LHip"], at["RHip"]]] = np.nan
    xb, yb = body_frame(x, y)
    assert np.isnan(yb[:2]).all()
    # frame 2 is the shoulders' third row and takes the third hip row's angle: frame 4's (20 degrees more)
    np.testing.assert_allclose(yb[2, at["LHip"]] - yb[2, at["RHip"]], 2 * np.sin(np.radians(-20.0)) / 2.0, atol=1e-12)


def test_short_clips_and_missing_joints_say_why() -> None:
    f = published_features(still_clip(24), SKEL, 30.0, SIZE)  # 0.8 s: the smoothing leaves no frame
    assert all(np.isnan(v) for v in f.values.values())
    assert "too short for the published windows" in f.reasons["Knee_mean_angle"]
    f = published_features(still_clip(33), SKEL, 30.0, SIZE)  # 1.1 s: angles yes, angular velocities no
    assert np.isfinite(f.values["mean_angle_LKnee"]) and np.isnan(f.values["median_vel_angle_LKnee"])
    assert "33 frames" in f.reasons["median_vel_angle_LKnee"]
    slow = published_features(still_clip(), SKEL, 3.0, SIZE)  # int(0.25 fps) = 0: no published windows
    assert all(np.isnan(v) for v in slow.values.values()) and "3 fps is too low" in slow.reasons["Ankle_IQRx"]
    assert all(np.isnan(v) for v in features_3d(np.zeros((90, 12, 3)), SKEL, 3.0).values.values())
    xy = still_clip()
    xy[:, SKEL.index("left_wrist")] = np.nan
    f = published_features(xy, SKEL, 25.0, SIZE)
    assert np.isnan(f.values["mean_angle_LElbow"]) and f.reasons["mean_angle_LElbow"] == "never detected: left_wrist"
    assert np.isnan(f.values["meanent_LWrist"])  # the published code gives 0: an entropy of nothing
    assert f.values["Elbow_mean_angle"] == f.values["mean_angle_RElbow"]  # the side that has one (merge_data_sets)
    assert np.isnan(f.values["lrCorr_angle_Elbow"]) and np.isfinite(f.values["lrCorr_angle_Knee"])


def test_3d_angles_follow_the_2d_convention_and_hardly_depend_on_the_camera() -> None:
    poses = kicking_poses(150)  # the left knee bends 0-60 degrees at 1 Hz, the right leg stays straight
    f = features_3d(poses, SKEL, 30.0).values
    assert f["3d_mean_angle_RKnee"] == pytest.approx(180.0, abs=1e-6)  # interior angle: straight = 180
    assert f["3d_median_vel_angle_RKnee"] == pytest.approx(0.0, abs=1e-6)
    assert 130.0 < f["3d_mean_angle_LKnee"] < 170.0 and f["3d_median_vel_angle_LKnee"] > 30.0
    assert f["3d_mean_angle_LHipFlexion"] == pytest.approx(0.0, abs=1e-6)
    moved = features_3d(poses + np.array([0.3, -0.1, 2.0]), SKEL, 30.0).values
    for name, value in f.items():
        assert moved[name] == pytest.approx(value, abs=1e-6, nan_ok=True), name
    # the published smoothing is a per-coordinate median: turning the camera changes the angles a little
    turned = features_3d(poses @ rotation(np.array([1.0, 2.0, 0.5]), 70.0).T, SKEL, 30.0).values
    assert turned["3d_mean_angle_LKnee"] == pytest.approx(f["3d_mean_angle_LKnee"], abs=0.5)
    assert turned["3d_median_vel_angle_LKnee"] == pytest.approx(f["3d_median_vel_angle_LKnee"], rel=0.02)


def test_mean_3d_dispersion_of_a_wrist_circling() -> None:
    t = np.arange(600) / 30.0  # 20 s at 30 fps, a circle of 3 cm every 10 s in the trunk's frontal plane
    poses = []
    for u in t:
        pts = standing()
        set_limb(pts, "left", "arm", 90.0, 0.0)
        pts["left_wrist"] = pts["left_wrist"] + 0.03 * np.array([np.cos(0.2 * np.pi * u), np.sin(0.2 * np.pi * u), 0])
        poses.append(to_array(pts))
    f = features_3d(np.array(poses), SKEL, 30.0).values
    assert f["3d_mean_dispersion_LWrist"] == pytest.approx(0.03 / 0.2, rel=0.02)  # trunk lengths (0.2 m)
    assert f["3d_mean_dispersion_RWrist"] == pytest.approx(0.0, abs=1e-9)


def test_analyze_emits_them_as_clip_rows(tmp_path: Path) -> None:
    path = write_document(tmp_path / "kick.zedo.json", result_document(kicking_poses(90), fps=30.0))
    a = analyse(read_result(path))
    clip = {r.measure: r for r in a.rows if r.frame_index is None}
    assert "left_knee_flexion_range_deg" in clip  # the existing features stay
    assert clip["Knee_mean_angle"].how == "none: published 2D feature" and clip["Knee_mean_angle"].unit == "deg"
    assert clip["mean_angle_RKnee"].value == pytest.approx(180.0, abs=1e-3)  # a straight leg, seen from the front
    assert clip["3d_mean_angle_RKnee"].how.startswith("none: no measure calibration")  # not the shipped prior
    assert np.isnan(clip["3d_mean_angle_RKnee"].low) and np.isnan(clip["3d_mean_angle_RKnee"].high)
    text = csv_text(a)
    assert "\n,,,0,Ankle_medianx," in text and "\n,,,0,3d_mean_dispersion_LAnkle," in text
    short = analyse(read_result(write_document(tmp_path / "s.zedo.json", result_document(kicking_poses(5)))),
                    AnalysisSettings(fps=30.0))  # fmt: skip
    row = next(r for r in short.rows if r.measure == "Elbow_mean_angle")
    assert np.isnan(row.value) and "too short for the published windows" in row.how


def test_a_result_without_2d_keypoints_gets_empty_published_features(tmp_path: Path) -> None:
    res = read_result(write_document(tmp_path / "k.zedo.json", result_document(kicking_poses(40), fps=30.0)))
    res.record = None
    clip = {r.measure: r for r in analyse(res).rows if r.frame_index is None}
    assert np.isnan(clip["Ankle_IQRx"].value)
    assert clip["Ankle_IQRx"].how == "none: the result file carries no 2D keypoints"
    assert np.isfinite(clip["3d_mean_angle_LKnee"].value)
