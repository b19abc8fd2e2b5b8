"""Input files that are not plain JSON files: inputs over the size
limit, FIFOs and devices refused before reading, symlink loops and broken links named as such,
file names with newlines or terminal escapes shown escaped on one line."""

from __future__ import annotations

import io
import os
import sys
from pathlib import Path

import pytest
from format_fixtures import coco_annotations, write_json
from typer.testing import CliRunner

from zedo_cli.cli import app
from zedo_cli.errors import InputFormatError
from zedo_cli.formats import read_keypoints
from zedo_cli.formats.readers import source

runner = CliRunner()


def test_an_input_over_the_limit_is_refused_before_reading(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = write_json(tmp_path / "big.json", coco_annotations())
    monkeypatch.setattr(source, "MAX_INPUT_BYTES", 100)
    opened: list[str] = []
    real_open = os.open
    monkeypatch.setattr(source.os, "open", lambda *a, **k: opened.append(a[0]) or real_open(*a, **k))
    with pytest.raises(InputFormatError, match=r"big\.json: larger than the input limit of 9.537e-05 MiB"):
        read_keypoints(path)
    assert opened == []  # refused from its size, never opened


def test_stdin_over_the_limit_is_refused(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(source, "MAX_INPUT_BYTES", 100)
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(b" " * 1000 + b"[]")))
    with pytest.raises(InputFormatError, match=r"^-: larger than the input limit"):
        read_keypoints("-")


def test_the_default_limit_is_documented() -> None:
    assert source.MAX_INPUT_BYTES == 256 * 2**20
    readme = (Path(__file__).resolve().parents[2] / "README.md").read_text()
    assert "256 MiB" in readme


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_a_fifo_is_refused_without_blocking(tmp_path: Path) -> None:
    fifo = tmp_path / "pipe.json"
    os.mkfifo(fifo)  # nobody writes: reading it would block forever
    with pytest.raises(InputFormatError, match=r"pipe\.json: is a FIFO"):
        read_keypoints(fifo)


@pytest.mark.skipif(not Path("/dev/zero").exists(), reason="no /dev/zero")
def test_dev_zero_is_refused_without_reading() -> None:
    with pytest.raises(InputFormatError, match=r"^/dev/zero: is a character device"):
        read_keypoints("/dev/zero")


def test_a_symlink_loop_and_a_broken_link_are_not_file_not_found(tmp_path: Path) -> None:
    loop = tmp_path / "loop.json"
    loop.symlink_to(loop)
    with pytest.raises(InputFormatError, match=r"loop\.json: symbolic link loop"):
        read_keypoints(loop)
    broken = tmp_path / "broken.json"
    broken.symlink_to(tmp_path / "gone.json")
    with pytest.raises(InputFormatError, match=r"broken\.json: broken symbolic link"):
        read_keypoints(broken)
    with pytest.raises(InputFormatError, match=r"missing\.json: file not found"):
        read_keypoints(tmp_path / "missing.json")


def test_the_cli_names_a_symlink_loop(tiny_prior_path: Path, tmp_path: Path) -> None:
    loop = tmp_path / "loop.json"
    loop.symlink_to(loop)
    result = runner.invoke(app, ["lift", str(loop), "--prior", str(tiny_prior_path), "-q"])
    assert result.exit_code == 3 and "symbolic link loop" in result.output and "not found" not in result.output


def test_file_names_with_newlines_and_escapes_are_shown_escaped(tmp_path: Path) -> None:
    name = tmp_path / "evil\n\x1b[31mred\x1b[0m.json"
    name.write_text("{not json")
    with pytest.raises(InputFormatError) as info:
        read_keypoints(name)
    message = str(info.value)
    assert "\n" not in message and "\x1b" not in message
    assert "evil\\n\\x1b[31mred\\x1b[0m.json: invalid JSON" in message


def test_json_keys_with_control_characters_stay_on_one_line() -> None:
    from zedo_cli.formats import read_parsed

    with pytest.raises(InputFormatError) as info:
        read_parsed({"meta_info": {"keypoint_id2name": {"a\nb": "nose"}}, "instance_info": []}, "m.json")
    assert "\n" not in str(info.value) and "a\\nb" in str(info.value)


def test_every_cli_error_about_a_file_name_stays_on_one_line(tiny_prior_path: Path, tmp_path: Path) -> None:
    """Not only the readers' messages: "file not found" of a name with a newline and an escape."""
    name = str(tmp_path / "no\nsuch\x1b[2J.json")
    result = runner.invoke(app, ["lift", name, "--prior", str(tiny_prior_path), "-q"])
    assert result.exit_code == 3 and result.output.count("\n") == 1 and "\x1b" not in result.output
    assert "no\\nsuch\\x1b[2J.json: " in result.output  # "no file matches this pattern": [ is a glob
