"""Hostile inputs at the command line: checks in the order a user needs them (usage, inputs,
outputs, then the prior), the silent cases made loud, and I/O failures as one line with a
documented exit code (5) that leave nothing behind."""

from __future__ import annotations

import errno
import json
from pathlib import Path

import pytest
from test_cli import lift_args, runner, write_coco

import zedo_cli.files as files_module
from zedo_cli.cli import app


@pytest.fixture
def no_prior(monkeypatch: pytest.MonkeyPatch) -> None:
    """The prior must not be loaded: the command fails before it."""

    def refuse(*args: object, **kwargs: object) -> None:
        raise AssertionError("the prior was loaded before the error")

    monkeypatch.setattr("zedo_cli.prior.weights.load_prior", refuse)


def _error_lines(output: str) -> list[str]:
    return [line for line in output.splitlines() if line.startswith("zedo: error:")]


@pytest.mark.parametrize(
    ("name", "content", "said"),
    [
        ("x.png", b"\x89PNG\r\n\x1a\n" + bytes(64), "this is an image (PNG)"),
        ("x.mp4", b"\x00\x00\x00\x20ftypisom" + bytes(64), "this is a video"),
        ("x.csv", b"frame,x,y\n0,1,2\n", "this is a CSV table"),
        ("x.npy", b"\x93NUMPY\x01\x00" + bytes(64), "this is a NumPy array"),
    ],
)
def test_a_wrong_kind_of_input_says_what_zedo_reads_before_outputs_and_prior(
    tiny_prior_path: Path, tmp_path: Path, no_prior: None, name: str, content: bytes, said: str
) -> None:
    src = tmp_path / name
    src.write_bytes(content)
    existing = tmp_path / "out.zedo.json"
    existing.write_text("{}")  # an existing output is reported after the input, not before
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "-o", str(existing)))
    assert result.exit_code == 3, result.output
    (line,) = _error_lines(result.output)
    assert line.startswith(f"zedo: error: {src}: {said}") and "2D detector's keypoints" in line


def test_a_malformed_single_input_fails_before_the_prior(tiny_prior_path: Path, tmp_path: Path, no_prior: None) -> None:
    src = tmp_path / "kp.json"
    src.write_text('{"people": [{"pose_keypoints_2d": [1, 2]}]}')
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "-o", str(tmp_path / "o.zedo.json")))
    assert result.exit_code == 3 and "pose_keypoints_2d" in result.output, result.output


def test_a_name_that_looks_like_an_emoji_code_is_printed_as_it_is(tmp_path: Path, no_prior: None) -> None:
    """rich would print `:baby:` as an emoji; zedo's consoles print names as they are."""
    src = tmp_path / "clip:baby:.json"
    result = runner.invoke(app, ["lift", str(src), "-o", str(tmp_path / "o.zedo.json")])
    assert result.exit_code == 3 and f"zedo: error: {src}: file not found" in result.output, result.output


@pytest.mark.parametrize(("out", "said"), [("/dev/null", "is a character device"), ("FOLDER", "is a folder")])
def test_an_output_that_is_not_a_file_is_refused_even_with_overwrite(
    tiny_prior_path: Path, tmp_path: Path, no_prior: None, out: str, said: str
) -> None:
    src = write_coco(tmp_path / "kp.json")
    target = str(tmp_path) if out == "FOLDER" else out
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "-o", target, "--overwrite"))
    assert result.exit_code == 2, result.output
    assert _error_lines(result.output) == [f"zedo: error: {target}: {said}; an output must be a file name "
                                           "(use - for stdout where it is offered)"]  # fmt: skip


def test_an_output_folder_the_system_refuses_fails_before_any_work(
    tiny_prior_path: Path, tmp_path: Path, no_prior: None
) -> None:
    src = write_coco(tmp_path / "kp.json")
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "-o", "/proc/zedo-test.zedo.json"))
    assert result.exit_code == 5, result.output
    assert _error_lines(result.output)[0].startswith("zedo: error: /proc/zedo-test.zedo.json: cannot write: ")
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "--plot", "/proc/zedo-plots"))
    assert result.exit_code == 5 and "/proc/zedo-plots: cannot write" in result.output, result.output


def test_a_full_disk_is_exit_5_and_leaves_nothing(
    tiny_prior_path: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    src = write_coco(tmp_path / "kp.json", n=1)
    plots = tmp_path / "plots"

    def full(a: object, b: object) -> None:
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(files_module.os, "replace", full)
    out = tmp_path / "kp.zedo.json"
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "-o", str(out), "--plot", str(plots)))
    assert result.exit_code == 5, result.output
    assert _error_lines(result.output) == [f"zedo: error: {plots}/kp.first.png: cannot write: No space left on device"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["kp.json", "plots"] and not list(plots.iterdir())


def _two_people(path: Path) -> Path:
    """Two persons in one image (image 10) and one alone in another (image 11)."""
    write_coco(path, n=3)
    doc = json.loads(path.read_text())
    doc["annotations"][1]["image_id"] = 10
    path.write_text(json.dumps(doc))
    return path


def test_person_choice_is_recorded_and_said_and_a_newline_name_stays_on_one_line(
    tiny_prior_path: Path, tmp_path: Path
) -> None:
    src = _two_people(tmp_path / "two\npeople.json")
    out = tmp_path / "o.zedo.json"
    result = runner.invoke(app, [a for a in lift_args(tiny_prior_path, str(src), "-o", str(out)) if a != "-q"])
    assert result.exit_code == 0, result.output
    selection = json.loads(out.read_text())["params"]["person_selection"]
    assert selection == {"mode": "auto", "frames": 2, "instances_read": 3, "instances_kept": 2, "left_out": 1,
                         "frames_with_several": 1}  # fmt: skip
    shown = str(src).replace("\n", "\\n")
    assert (f"zedo: warning: {shown}: --person auto kept one person per frame: 2 instances of 3; 1 instance left "
            "out in 1 frame with several people") in result.output  # fmt: skip
    assert "lifted 2/2 instances" in result.output
    assert not any(line.startswith("people.json") for line in result.output.splitlines())  # never split


def test_batch_summary_names_each_failure_once_with_its_full_path(tiny_prior_path: Path, tmp_path: Path) -> None:
    deep = tmp_path / ("a_rather_long_folder_name_" * 4)
    deep.mkdir()
    good, bad = write_coco(deep / "good.json", n=1), deep / "bad.json"
    bad.write_text('{"' + "x" * 300 + '": 1}')  # the message names the key: a long message
    result = runner.invoke(app, [a for a in lift_args(tiny_prior_path, str(good), str(bad)) if a != "-q"])
    assert result.exit_code == 4, result.output
    assert result.output.count("x" * 300) == 1  # the error once, not again in the table
    table = result.output[result.output.index("zedo lift: 2 inputs, 1 failed") :]
    assert "failed, exit code 3" in table and "…" not in table
    assert str(bad) in "".join(line.strip("│ ").split("│")[0].strip() for line in table.splitlines())
