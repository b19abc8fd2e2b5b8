"""The head measures: tilt sign and range whichever way the infant lies, the turn rule on
constructed faces, the reasons of missing points, and the clip shares against the frame rows."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest
from analysis_results import kicking_poses, result_document, write_document
from helpers import K_TEST

from zedo_cli.analysis.analyse import AnalysisSettings, analyse, summary
from zedo_cli.analysis.pose.head import FLAG_EYES_REVERSED, HeadSettings, head_tilt, head_turn
from zedo_cli.analysis.uncertainty.block_bootstrap import (
    BootstrapSettings,
    block_length,
    median_interval,
    share_intervals,
    taper_correction,
)
from zedo_cli.data.keypoints import OtherKeypoints
from zedo_cli.formats.readers.result import read_result

# An infant's face in head coordinates (cm): x its own left, y towards the top of its head, z out of its face.
FACE_CM = {"nose": (0.0, -0.8, 6.5), "left_eye": (1.95, 1.2, 5.2), "right_eye": (-1.95, 1.2, 5.2),
           "left_ear": (4.75, 0.0, 0.0), "right_ear": (-4.75, 0.0, 0.0)}  # fmt: skip
SHOULDERS_CM = np.array([[6.5, -9.0], [-6.5, -9.0]])  # left, right: (x, y) in the body's plane


def view(yaw: float = 0.0, roll: float = 0.0, *, angle: float = 0.0, mirror: bool = False,
         drop: tuple[str, ...] = ()) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """Face `(1, 5, 2)` and shoulders `(1, 2, 2)` in pixels of an infant lying with its chest to the
    camera, its face turned by `yaw` (degrees, + to its left) and tilted by `roll` (+ towards its
    left shoulder), seen orthographically; the picture rotated by `angle` degrees, and mirrored
    (seen from behind) with `mirror`."""
    a, r = math.radians(yaw), math.radians(roll)
    pts = []
    for name, (x, y, z) in FACE_CM.items():
        x1 = x * math.cos(a) + z * math.sin(a)
        x2, y2 = x1 * math.cos(r) + y * math.sin(r), -x1 * math.sin(r) + y * math.cos(r)
        pts.append((np.nan, np.nan) if name in drop else (x2, y2))
    body = np.concatenate([np.array(pts), SHOULDERS_CM])  # (7, 2) x to its left, y to its head
    # front view: its left on the image's right, its head up (image y down)
    img = np.stack([body[:, 0], -body[:, 1]], axis=1)
    if mirror:  # seen from behind: its left on the image's left
        img[:, 0] *= -1.0
    c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    img = img @ np.array([[c, s], [-s, c]]) * 10.0 + 300.0
    return img[None, :5], img[None, 5:]


@pytest.mark.parametrize("angle", [0.0, 90.0, 180.0, 251.0])
@pytest.mark.parametrize("mirror", [False, True])
def test_tilt_sign_and_size_whichever_way_the_infant_lies(angle: float, mirror: bool) -> None:
    for roll in (-40.0, -7.5, 0.0, 12.0, 60.0):
        tilt, how, flag = head_tilt(*view(roll=roll, angle=angle, mirror=mirror))
        assert tilt[0] == pytest.approx(roll, abs=1e-9), (roll, angle, mirror)
        assert how[0].startswith("none: not calibrated") and flag[0] == ""


def test_tilt_range_and_a_reversed_eye_line() -> None:
    face, shoulders = view()
    face = face[:, [0, 2, 1, 4, 3]]  # eyes and ears swapped: the eye line points against the shoulder line
    tilt, _, flag = head_tilt(face, shoulders)
    assert tilt[0] == 90.0 or -90.0 < tilt[0] <= 90.0
    assert tilt[0] == pytest.approx(0.0, abs=1e-9) and flag[0] == FLAG_EYES_REVERSED
    face, shoulders = view(roll=90.0)
    assert head_tilt(face, shoulders)[0][0] == pytest.approx(90.0)  # -90 folds to +90: (-90, 90]


@pytest.mark.parametrize("angle", [0.0, 137.0])
@pytest.mark.parametrize("mirror", [False, True])
def test_turn_calls_and_yaw_to_the_infants_own_side(angle: float, mirror: bool) -> None:
    for yaw, call in ((0.0, "midline"), (12.0, "midline"), (-15.0, "midline"), (30.0, "left"), (-45.0, "right")):
        value, calls, how = head_turn(*view(yaw, angle=angle, mirror=mirror))
        assert calls[0] == call and value[0] == pytest.approx(yaw, abs=0.2), (yaw, angle, mirror)
        assert "nose between the ears and the nose between the eyes" in how[0]


def test_turn_from_the_points_that_show() -> None:
    value, call, how = head_turn(*view(-35.0, drop=("right_ear",)))
    assert call[0] == "right" and value[0] == pytest.approx(-35.0, abs=0.5) and "the nose between the eyes, " in how[0]
    value, call, how = head_turn(*view(-70.0, drop=("right_eye", "right_ear")))  # far: one side of the face only
    assert call[0] == "right" and np.isnan(value[0]) and "(right eye hidden)" in how[0]
    value, call, how = head_turn(*view(80.0, drop=("left_eye", "right_eye", "left_ear")))
    assert call[0] == "left" and np.isnan(value[0]) and "(left ear hidden)" in how[0]
    value, call, how = head_turn(*view(0.0, drop=("nose",)))  # no nose: the eyes between the ears
    assert call[0] == "midline" and "eyes between the ears" in how[0]
    # one eye missing at midline looks like a turn to its side (a detector's dropout is miscalled)
    assert head_turn(*view(0.0, drop=("left_eye", "left_ear")))[1][0] == "left"
    # the points contradict each other: the nose beyond the visible eye on its own side, or hidden sides that differ
    value, call, how = head_turn(*view(-80.0, drop=("left_eye", "left_ear")))
    assert call[0] == "" and np.isnan(value[0]) and "contradict" in how[0]
    assert "contradict" in head_turn(*view(-70.0, drop=("right_eye", "left_ear")))[2][0]


def test_reasons_for_missing_points() -> None:
    tilt, how, _ = head_tilt(*view(drop=("left_eye",)))
    assert np.isnan(tilt[0]) and how[0] == "none: missing: left_eye"
    face, shoulders = view()
    shoulders[0, 1] = np.nan
    assert head_tilt(face, shoulders)[1][0] == "none: missing: right_shoulder"
    value, call, how = head_turn(face, shoulders)
    assert np.isnan(value[0]) and call[0] == "" and how[0] == "none: missing: right_shoulder"
    _, call, how = head_turn(*view(drop=("nose", "left_eye", "right_eye")))
    assert call[0] == "" and how[0] == "none: face not visible (no nose, no eyes)"
    face, shoulders = view()
    shoulders[0, 0] = shoulders[0, 1] + 0.2 * (face[0, 1] - face[0, 2])  # shoulders nearer than the eyes: on its side
    assert "foreshortened" in head_tilt(face, shoulders)[1][0] and "foreshortened" in head_turn(face, shoulders)[2][0]


def _result_with_faces(tmp_path: Path, yaws: np.ndarray, fps: float | None = 30.0, face: bool = True) -> Path:
    """A result of len(yaws) frames whose input had faces turned by `yaws` (+ its left), or none."""
    poses = kicking_poses(len(yaws))  # standing in front of the camera: its left on the image's right
    doc_kp = result_document(poses, fps=fps)
    uv = poses @ K_TEST.T
    xy = uv[..., :2] / uv[..., 2:]  # (N, 12, 2)
    ls, rs = xy[:, 9], xy[:, 6]  # syrip12: left / right shoulder
    scale = np.linalg.norm(ls - rs, axis=-1)[:, None] / 13.0  # pixels per cm
    faces = []
    for n, yaw in enumerate(yaws):
        f, s = view(float(yaw))
        f = (f[0] - s[0].mean(0)) / 10.0  # cm about the shoulders' midpoint, image axes
        faces.append(0.5 * (ls[n] + rs[n]) + f * scale[n])
    names = tuple(FACE_CM) if face else ("left_big_toe",)
    pts = np.array(faces) if face else np.full((len(yaws), 1, 2), 5.0)
    other = OtherKeypoints(names, pts, np.ones(pts.shape[:2]))
    for n, fr in enumerate(doc_kp["frames"]):  # as zedo lift writes them
        fr["persons"][0]["other_keypoints_2d"] = pts[n].tolist()
        fr["persons"][0]["other_keypoint_confidence"] = other.confidence[n].tolist()
    doc_kp = {"other_keypoints": {"joints": list(names)}, **doc_kp}
    return write_document(tmp_path / "faces.zedo.json", doc_kp)


def test_clip_shares_are_the_frame_rows_calls_counted(tmp_path: Path) -> None:
    yaws = np.concatenate([np.zeros(60), np.full(90, -50.0), np.linspace(-50, 50, 30), np.full(60, 45.0)])
    a = analyse(read_result(_result_with_faces(tmp_path, yaws)))
    calls = [r.call for r in a.rows if r.measure == "head_turn" and r.frame_index is not None]
    clip = {r.measure: r for r in a.rows if r.frame_index is None and r.measure.startswith("head_")}
    for c in ("left", "right", "midline"):
        share = clip[f"head_turn_fraction_{c}"]
        assert share.value == calls.count(c) / sum(1 for x in calls if x)
        assert share.low <= share.value <= share.high and share.how.startswith("calibrated: circular block bootstrap")
    assert calls.count("right") >= 90 and calls.count("midline") >= 60
    assert clip["head_tilt_median_deg"].value == pytest.approx(0.0, abs=1e-6)
    assert not any("no head measures" in n for n in a.notes)
    counts = summary(a)["head_turn"]
    assert counts["count"] == sum(1 for x in calls if x) and counts["right"] == calls.count("right")


def test_a_result_without_face_points_says_so_once(tmp_path: Path) -> None:
    a = analyse(read_result(_result_with_faces(tmp_path, np.zeros(20), face=False)))
    head = [r for r in a.rows if r.measure.startswith("head_")]
    assert len(head) == 20 * 2 + 4 and all(np.isnan(r.value) for r in head)
    assert all(r.how == "none: the input has no face points (nose, eyes, ears)" for r in head)
    assert [n for n in a.notes if "head" in n] == ["no head measures: the input has no face points (nose, eyes, ears)"]


def test_low_confidence_face_points_are_missing_as_lift_made_them(tmp_path: Path) -> None:
    path = _result_with_faces(tmp_path, np.zeros(5), fps=None)
    res = read_result(path)
    res.other_keypoint_confidence[:, 0] = 0.2  # the nose
    a = analyse(dataclasses.replace(res, params={**res.params, "min_confidence": 0.3}))
    turns = [r for r in a.rows if r.measure == "head_turn"]
    assert all("eyes between the ears" in r.how for r in turns)  # the nose left out
    a = analyse(res, AnalysisSettings(head=HeadSettings(min_confidence=0.1)))
    assert all("nose between" in r.how for r in a.rows if r.measure == "head_turn")


def test_block_length_grows_with_the_correlation() -> None:
    rng = np.random.default_rng(1)
    white = rng.normal(size=3000)
    ar = np.zeros(3000)
    for t in range(1, 3000):
        ar[t] = 0.95 * ar[t - 1] + rng.normal()
    assert block_length(white) < 5.0 < block_length(ar)
    assert block_length(np.ones(100)) == 0.0
    assert taper_correction(white, 30) < 1.1 < taper_correction(ar, 30) <= 2.0


def test_bootstrap_intervals_hold_the_estimate_and_refuse_short_series() -> None:
    rng = np.random.default_rng(2)
    calls = np.repeat(rng.integers(0, 3, 60), 30)  # holds of 1 s at 30 fps
    ind = np.stack([(calls == c).astype(float) for c in range(3)])
    ind[:, ::7] = np.nan  # frames without a call
    out = share_intervals(ind, 30.0, BootstrapSettings(replicates=300))
    for c, i in enumerate(out):
        share = np.nansum(ind[c]) / np.isfinite(ind[c]).sum()
        assert i.low <= share <= i.high and i.block >= 30
    med = median_interval(np.where(np.isfinite(ind[0]), calls * 10.0, np.nan), 30.0)
    assert med.low <= np.median(calls * 10.0) <= med.high
    short = share_intervals(ind[:, :40], 30.0)
    assert np.isnan(short[0].low) and short[0].how.startswith("none: too few frames")
