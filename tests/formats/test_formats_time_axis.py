"""The time axis is kept: OpenPose frame numbers from file names reach the
output's ``frame_index`` (empty frames never shift later ones), AlphaPose timestamps are not
merged by their trailing digits, a Pose2Sim folder without ``_keypoints`` is one sequence, and
the temporal filter never blends across a long gap of missing frames."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from format_fixtures import alphapose, flat, openpose_frame, write_json
from typer.testing import CliRunner

from zedo_cli.cli import app
from zedo_cli.cli.lift_plan import expand_inputs
from zedo_cli.formats import read_keypoints, read_parsed
from zedo_cli.formats.readers.openpose import is_openpose_folder
from zedo_cli.formats.writers.common import group_frames
from zedo_cli.lifting.people import select_people

runner = CliRunner()
EMPTY = {"version": 1.3, "people": []}


def _clip(folder: Path, frames: list[int], empty: list[int], name: str = "clip_{:012d}_keypoints.json") -> Path:
    folder.mkdir()
    for f in frames:
        write_json(folder / name.format(f), EMPTY if f in empty else openpose_frame(50.0 + f))
    return folder


def test_openpose_empty_frames_keep_their_gap_in_frame_index(tiny_prior_path: Path, tmp_path: Path) -> None:
    """11 empty frames (1-11) between frame 0 and frame 12: frame 12 stays 12, not 1."""
    folder = _clip(tmp_path / "op", list(range(14)), empty=list(range(1, 12)))
    kp = read_keypoints(folder)
    assert kp.frame_indices == [0, 12, 13]
    base = ["lift", str(folder), "--prior", str(tiny_prior_path), "--steps", "10", "-q", "--image-size", "640", "480"]
    result = runner.invoke(app, [*base, "-o", "-"])
    assert result.exit_code == 0, result.output
    assert [f["frame_index"] for f in json.loads(result.stdout)["frames"]] == [0, 12, 13]
    result = runner.invoke(app, [*base, "-o", "-", "--output-format", "csv"])
    assert {line.split(",")[0] for line in result.stdout.splitlines()[1:]} == {"0", "12", "13"}
    out = tmp_path / "op.zedo.npz"
    assert runner.invoke(app, [*base, "-o", str(out)]).exit_code == 0
    assert np.load(out)["frame_index"].tolist() == [0, 12, 13]


def test_frame_numbers_fall_back_to_positions_when_they_would_merge_frames() -> None:
    assert group_frames(["a", "b", "c"], [0, 12, 13]).frame_index.tolist() == [0, 12, 13]
    assert group_frames(["a", "b", "b"], [4, 7, 7]).frame_index.tolist() == [4, 7, 7]
    assert group_frames(["a", "b"], [5, 5]).frame_index.tolist() == [0, 1]  # two images, one number
    assert group_frames(["a", "b"], [5, None]).frame_index.tolist() == [0, 1]
    assert group_frames(["a", "b"]).frame_index.tolist() == [0, 1]


def test_alphapose_timestamps_are_not_merged_by_trailing_digits() -> None:
    """ "1650000000.5.jpg" and "1650000001.5.jpg" both end in 5: they were one frame."""
    doc = alphapose(count=17)[:2]
    doc[0]["image_id"], doc[1]["image_id"] = "1650000001.5.jpg", "1650000000.5.jpg"
    kp = read_parsed(doc, "ap.json")
    assert kp.image_ids == ["1650000000.5.jpg", "1650000001.5.jpg"] and kp.frame_indices == [0, 1]
    assert len(select_people(kp, "auto").index) == 2  # one person per image, none dropped
    plain = read_parsed(alphapose(count=17), "ap.json")  # "2.jpg", "10.jpg": their own numbers
    assert plain.frame_indices == [2, 2, 10]


def test_pose2sim_folder_without_keypoints_suffix_is_one_sequence(tiny_prior_path: Path, tmp_path: Path) -> None:
    folder = _clip(tmp_path / "cam01", [28, 29, 30, 31], empty=[29], name="cam01.{:04d}.json")
    (folder / "cam01.zedo.json").write_text("{}")  # an earlier output is not a frame
    assert is_openpose_folder(folder) and expand_inputs([str(folder)]) == [str(folder)]
    kp = read_keypoints(folder)
    assert kp.image_ids == ["cam01.0028", "cam01.0030", "cam01.0031"] and kp.frame_indices == [28, 30, 31]
    result = runner.invoke(app, ["lift", str(folder), "--prior", str(tiny_prior_path), "--steps", "10", "-q",
                                 "--image-size", "640", "480", "-o", "-"])  # fmt: skip
    assert result.exit_code == 0, result.output
    assert [f["frame_index"] for f in json.loads(result.stdout)["frames"]] == [28, 30, 31]


def test_a_folder_of_other_files_is_not_one_sequence(tmp_path: Path) -> None:
    folder = tmp_path / "mixed"
    folder.mkdir()
    write_json(folder / "a.json", {"people": []})
    write_json(folder / "b.json", [{"image_id": 1, "keypoints": flat(17, 1.0)}])
    assert not is_openpose_folder(folder)
    assert expand_inputs([str(folder)]) == [str(folder / "a.json"), str(folder / "b.json")]
    other = tmp_path / "two_videos"
    other.mkdir()
    write_json(other / "left.0001.json", openpose_frame(1.0))
    write_json(other / "right.0001.json", openpose_frame(1.0))
    assert not is_openpose_folder(other)


def test_temporal_smoothing_does_not_blend_across_a_long_gap(tiny_prior_path: Path, tmp_path: Path) -> None:
    """Frames 0-5, then 30-35 (a gap of 24 frames, wider than the filter's 3 sigma = 6): the
    first part's smoothed poses are those of the first part lifted alone."""
    both = _clip(tmp_path / "both", [*range(6), *range(30, 36)], empty=[])
    alone = _clip(tmp_path / "alone", list(range(6)), empty=[])
    poses = []
    for folder in (both, alone):
        result = runner.invoke(app, ["lift", str(folder), "--prior", str(tiny_prior_path), "--steps", "10", "-q",
                                     "--image-size", "640", "480", "--temporal", "smooth", "-o", "-"])  # fmt: skip
        assert result.exit_code == 0, result.output
        poses.append([f["persons"][0]["keypoints_3d_root_relative"] for f in json.loads(result.stdout)["frames"]])
    # Equal up to float rounding (a batch of 12 and one of 6 may round differently on some CPUs);
    # blending across the gap would move joints by millimetres.
    diff = np.abs(np.array(poses[0][:6]) - np.array(poses[1])).max()
    assert diff < 1e-5
