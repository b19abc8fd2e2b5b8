"""The clip report (a result with fps): its summary, plots, frames to review and thumbnails; the plain
words of every clip feature; the refusal of footage that is not the result's."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np
import pytest
from analysis_results import kicking_poses, result_document, write_document
from typer.testing import CliRunner

from zedo_cli.analysis.analyse import analyse
from zedo_cli.analysis.clip.features_3d import PREFIX
from zedo_cli.analysis.clip.published_features import PREREGISTERED
from zedo_cli.analysis.report.plain_words import describe, has_words
from zedo_cli.cli import app
from zedo_cli.formats.readers.result import read_result


@pytest.fixture()
def clip(tmp_path: Path) -> tuple[Path, list]:
    """A 30 fps kicking clip whose params match a test calibration of +-5 degrees (some calls uncertain)."""
    from test_calibration import PARAMS, calibration

    doc = result_document(kicking_poses(60), fps=30.0)
    doc["params"].update({**PARAMS, "temporal": {"mode": "smooth"}})
    return write_document(tmp_path / "clip.zedo.json", doc), [calibration("smooth")]


def _video(path: Path, frames: int, size: tuple[int, int] = (640, 480)) -> Path:
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"mp4v"), 30.0, size)
    for i in range(frames):
        writer.write(np.full((size[1], size[0], 3), 40 + 3 * i, np.uint8))
    writer.release()
    return path


def test_the_clip_report_leads_with_the_summary(clip: tuple[Path, list]) -> None:
    from zedo_cli.analysis.report.report import report_html

    a = analyse(read_result(clip[0]), calibrations=clip[1])
    page = report_html(a)
    at = {h: page.index(h) for h in ("For research; not a diagnosis", "Summary of the recording", "Over time",
                                     "Frames to review", "Decisions")}  # fmt: skip
    assert list(at.values()) == sorted(at.values())  # the notice, then summary, plots, review, then the rest
    summary = page[at["Summary of the recording"] : at["Over time"]]
    for pair in ("upper arm", "forearm", "thigh", "shank"):
        assert pair in summary
    share = next(r for r in a.rows if r.measure == "symmetry_thigh_share_asymmetric")
    assert f"{100 * share.value:.0f} %" in summary and "90 % interval" in summary
    assert "Head</b>: not measured" in summary  # no face points in this clip: said once, not four dashes
    assert "No comparison with typical infants" in summary
    review = page[at["Frames to review"] : at["Decisions"]]
    assert "symmetry calls uncertain" in review and "<th>time (s)</th>" in review  # no footage: a list
    assert "<img" not in page


def test_review_picks_are_spread_and_most_undecided_first(clip: tuple[Path, list]) -> None:
    from zedo_cli.analysis.report.clip_report import review_picks, uncertain

    a = analyse(read_result(clip[0]), calibrations=clip[1])
    picks = review_picks(a, count=4)
    assert 0 < len(picks) <= 4
    assert all(p.uncertain > 0 or p.flagged for p in picks)
    assert [p.score for p in picks] == sorted((p.score for p in picks), reverse=True)
    assert len({p.frame_index for p in picks}) == len(picks)
    assert sum(uncertain(a) > 0) >= len(picks)


def test_plain_words_cover_every_published_and_3d_feature(clip: tuple[Path, list]) -> None:
    a = analyse(read_result(clip[0]), calibrations=clip[1])
    names = {r.measure for r in a.rows if r.frame_index is None}
    published = {n for n in names if n in PREREGISTERED or n.startswith(("mean_angle_", "medianx_", "lrCorr_"))}
    three_d = {n for n in names if n.startswith(PREFIX)}
    assert set(PREREGISTERED) <= names and len(PREREGISTERED) == 38 and len(three_d) > 30
    for n in set(PREREGISTERED) | published | three_d:
        assert has_words(n), n
        assert "_" not in describe(n, 1.0).split(" (z")[0], n  # words, not the raw name
    assert describe("mean_angle_LElbow", -4.1) == "left elbow: held at a smaller angle than typical (z = -4.1)"
    assert describe("3d_median_vel_angle_RHipFlexion", 2.0).startswith("right hip flexion (3D): moves faster")
    assert describe("Wrist_IQRx", 3.0).startswith("wrists (both sides): moves over a wider range")
    assert not has_words("no_such_feature")


def test_thumbnails_cut_from_a_video_and_a_mismatched_video_refused(clip: tuple[Path, list], tmp_path: Path) -> None:
    from zedo_cli.analysis.report.clip_report import review_picks
    from zedo_cli.analysis.report.report import Footage, report_html
    from zedo_cli.footage.thumbnails import THUMB_WIDTH, cut_thumbnails
    from zedo_cli.footage.video_check import VideoMismatchError

    a = analyse(read_result(clip[0]), calibrations=clip[1])
    picks = review_picks(a)
    video = _video(tmp_path / "clip.mp4", 60)
    thumbs = cut_thumbnails(a.result, [p.frame_index for p in picks], video=video)
    assert set(thumbs) == {p.frame_index for p in picks}
    first = cv2.imdecode(np.frombuffer(thumbs[picks[0].frame_index], np.uint8), cv2.IMREAD_COLOR)
    assert first.shape[1] == THUMB_WIDTH and first.std() > 0  # the skeleton drawn over a plain frame
    page = report_html(a, Footage(picks, thumbs))
    assert page.count("<img alt='frame") == len(picks) and "data:image/png;base64," in page
    with pytest.raises(VideoMismatchError, match="20 frames, but the result .* has people in frame 59"):
        cut_thumbnails(a.result, [0], video=_video(tmp_path / "short.mp4", 20))
    with pytest.raises(VideoMismatchError, match="lifted for a 640x480 image"):
        cut_thumbnails(a.result, [0], video=_video(tmp_path / "wide.mp4", 60, (320, 240)))


def test_analyze_refuses_footage_that_does_not_fit_in_one_line(clip: tuple[Path, list], tmp_path: Path) -> None:
    short = _video(tmp_path / "short.mp4", 20)
    out = CliRunner().invoke(app, ["analyze", str(clip[0]), "--report", str(tmp_path / "r"), "--video", str(short),
                                   "-o", str(tmp_path / "a.csv"), "-q"])  # fmt: skip
    assert out.exit_code == 3, out.output
    assert "short.mp4: 20 frames" in out.output and len(out.output.strip().splitlines()) == 1
    assert not (tmp_path / "a.csv").exists()
    out = CliRunner().invoke(app, ["analyze", str(clip[0]), "--video", str(short)])
    assert out.exit_code != 0 and "--report" in out.output


def test_plain_words_for_the_comparisons_other_features() -> None:
    assert describe("asym_logratio_3d_median_vel_angle_Elbow", 2.5) == (
        "elbows (3D), left against right: on the left, moves faster (relative to the right) than typical (z = +2.5)"
    )
    assert describe("left_knee_flexion_range_deg", -2.3) == (
        "left knee flexion: moves through a smaller range than typical (z = -2.3)"
    )
    assert describe("symmetry_thigh_share_asymmetric", 3.0).startswith("thigh symmetry: asymmetric in more frames")
    assert describe("head_turn_fraction_left", -1.0).startswith("head: head turned left in fewer frames")


def test_a_thumbnail_keeps_the_head_in_view_without_face_points(clip: tuple[Path, list]) -> None:
    """A body-only skeleton has no head point: the crop reaches HEAD_REACH trunk lengths beyond the
    shoulders, so the crown a reviewer looks for (head turn) is not cut off."""
    from zedo_cli.footage.render import Painter, RenderSettings
    from zedo_cli.footage.thumbnails import HEAD_REACH, _around, _with_head

    result = read_result(clip[0])
    assert result.other_keypoints_2d is None
    px = Painter(result, RenderSettings()).persons[0].px + 700.0  # the person in the middle of the frame below
    names = list(result.skeleton.joints)
    shoulders = px[[names.index("left_shoulder"), names.index("right_shoulder")]].mean(0)
    hips = px[[names.index("left_hip"), names.index("right_hip")]].mean(0)
    crown = shoulders + HEAD_REACH * (shoulders - hips)
    kept = _with_head(result, 0, px)
    assert len(kept) == len(px) + 1 and np.allclose(kept[-1], crown)
    frame = np.zeros((1600, 1600), np.uint8)  # room around the person: no clipping at the frame's edge
    frame[int(round(crown[1])), int(round(crown[0]))] = 255
    assert _around(frame, [kept]).max() == 255
    assert _around(frame, [px]).max() == 0  # the joints alone crop the crown away


def test_depth_ambiguous_frames_are_shaded_and_said(tmp_path: Path) -> None:
    from zedo_cli.analysis.report.clip_report import AMBIGUOUS_SHADE, decimate, depth_ambiguous, time_series_section

    doc = result_document(kicking_poses(60), fps=30.0)
    for frame in doc["frames"][20:30]:
        frame["persons"][0]["flags"] = ["depth_ambiguous: left_ankle"]
    a = analyse(read_result(write_document(tmp_path / "amb.zedo.json", doc)))
    flagged = depth_ambiguous(a)
    assert flagged.sum() == 10 and flagged[20:30].all()
    assert decimate(a, 0).ambiguous.sum() == 10
    assert f"background:{AMBIGUOUS_SHADE}'>a limb's depth side ambiguous" in time_series_section(a)
    plain = analyse(
        read_result(write_document(tmp_path / "plain.zedo.json", result_document(kicking_poses(60), fps=30.0)))
    )
    assert not depth_ambiguous(plain).any() and "depth side ambiguous" not in time_series_section(plain)


def test_with_a_reference_the_summary_says_what_share_asymmetric_is_typical(clip: tuple[Path, list]) -> None:
    from zedo_cli.analysis.norms.norms import ClipValues, Norms
    from zedo_cli.analysis.report.clip_report import summary_section, typical_shares_row

    a = analyse(read_result(clip[0]), calibrations=clip[1])
    assert typical_shares_row(a) == ""  # no reference: nothing said
    shares = np.linspace(0.2, 0.6, 20)
    clips = [ClipValues(f"c{i}", 0, {"symmetry_thigh_share_asymmetric": float(s)}) for i, s in enumerate(shares)]
    a = replace(a, reference=Norms(["all"], {"all": {}}, clips, ["all"] * 20))
    summary = summary_section(a)
    lo, mid, hi = np.quantile(shares, [0.1, 0.5, 0.9])
    assert (
        f"{100 * mid:.0f} % <small>typical: 20 reference clips, middle 80 % {100 * lo:.0f} % – {100 * hi:.0f} %"
        in summary
    )
    assert summary.count("(not in the reference)") == 3  # the other pairs' shares are not in this reference


def test_epochs_summarise_each_epoch_as_a_loop_over_epochs_would() -> None:
    from zedo_cli.analysis.report.epochs import Epochs

    rng = np.random.default_rng(0)
    epoch = np.sort(rng.choice([0, 1, 3, 4], 200))  # epoch 2 has no frames: a gap in the track
    values = rng.normal(50.0, 20.0, 200)
    values[rng.random(200) < 0.1] = np.nan
    pos = rng.permutation(200)  # the track's frames, in time order, at these positions of the analysis
    ep = Epochs(pos, epoch, np.arange(5) * 10.0 + 5.0, 10.0)
    got = ep.quartiles(values)
    for e in range(5):
        mine = values[pos[epoch == e]]
        want = np.nanpercentile(mine, [25, 50, 75]) if np.isfinite(mine).any() else np.full(3, np.nan)
        np.testing.assert_allclose(got[:, e], want, equal_nan=True)
    flag = values > 50
    share = ep.mean(flag)
    assert np.isnan(share[2]) and share[0] == pytest.approx(flag[pos[epoch == 0]].mean())


def test_a_long_track_is_drawn_by_epochs_and_a_short_one_frame_by_frame(tmp_path: Path) -> None:
    from zedo_cli.analysis.report.clip_report import time_series_section
    from zedo_cli.analysis.report.epochs import SUMMARY_OVER_S, epochs_of

    long = analyse(read_result(write_document(tmp_path / "long.zedo.json",
                                              result_document(kicking_poses(400), fps=1.0))))  # fmt: skip
    ep = epochs_of(long, 0)
    assert ep is not None and ep.seconds == 10.0 and len(ep.t) == 40  # 399 s by epochs of 10 s
    assert "drawn by epochs of 10 s" in time_series_section(long) and "<svg" in time_series_section(long)
    short = analyse(read_result(write_document(tmp_path / "short.zedo.json",
                                               result_document(kicking_poses(60), fps=30.0))))  # fmt: skip
    assert epochs_of(short, 0) is None and SUMMARY_OVER_S > 2.0
    assert "drawn by epochs" not in time_series_section(short)
