"""One contract for every command (docs/cli.md): the same option names, help that fits a
screen, a short usage without arguments, plain logs off a terminal, output folders made alike."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
import typer.main
from helpers import write_coco
from typer.testing import CliRunner

from zedo_cli.cli import app
from zedo_cli.version import __version__

runner = CliRunner()
COMMANDS = typer.main.get_command(app).commands  # type: ignore[attr-defined]
DOCS = Path(__file__).resolve().parents[2] / "docs" / "cli.md"


def lift_args(prior: Path, *extra: str) -> list[str]:
    return ["lift", "--prior", str(prior), "--steps", "30", *extra]


def _opts(name: str) -> dict[str, object]:
    return {o: p for p in COMMANDS[name].params for o in p.opts}


def test_version() -> None:
    result = runner.invoke(app, ["--version"])
    assert result.exit_code == 0 and result.stdout.strip() == f"zedo {__version__}"


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_every_command_has_the_shared_options_under_one_name(name: str) -> None:
    opts = _opts(name)
    assert "-q" in opts and opts["-q"].opts == ["--quiet", "-q"]  # type: ignore[attr-defined]
    assert "-o" in opts, f"{name} writes something: it takes -o/--output"
    assert opts["-o"].opts == ["--output", "-o", "--out"]  # type: ignore[attr-defined]
    assert "--overwrite" in opts
    if "--json" in opts:  # a switch everywhere, never a path
        assert opts["--json"].is_flag  # type: ignore[attr-defined]
    assert f"`{name}`" in DOCS.read_text() or name.startswith("benchmark-") or name == "fit-augmenter"


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_help_fits_80_columns_and_cuts_nothing(name: str) -> None:
    result = runner.invoke(app, [name, "--help"], env={"COLUMNS": "80"}, terminal_width=80)
    assert result.exit_code == 0
    lines = result.stdout.splitlines()
    assert lines[0].startswith(f"Usage: zedo {name} [OPTIONS]")
    assert all(len(line) <= 80 for line in lines), max(lines, key=len)
    assert "…" not in result.stdout and not any(line != line.rstrip() for line in lines)
    for param in COMMANDS[name].params:  # every option's name whole
        if not getattr(param, "hidden", False) and param.opts[0].startswith("--"):
            assert param.opts[0] in result.stdout


def test_lift_help_is_a_screen_of_panels() -> None:
    result = runner.invoke(app, ["lift", "--help"], env={"COLUMNS": "80"}, terminal_width=80)
    text = result.stdout
    assert len(text.splitlines()) <= 200
    assert text.splitlines()[0] == "Usage: zedo lift [OPTIONS] KEYPOINTS..."
    panels = re.findall(r"╭─ ([A-Za-z ,:()-]+?) ─", text)
    assert panels[:5] == ["Input", "Camera", "Lifting", "Lifting, expert (other values: no calibrated uncertainty)",
                          "Output"] and "Performance" in panels  # fmt: skip
    assert "-o, --output PATH" in text and "--out " not in text  # the older spelling is read, not shown


@pytest.mark.parametrize("name", ["lift", "analyze", "render", "evaluate"])
def test_a_bare_command_shows_a_short_usage_and_a_hint(name: str) -> None:
    result = runner.invoke(app, [name])
    assert result.exit_code == 2
    lines = result.stderr.strip().splitlines()
    assert lines[0].startswith(f"Usage: zedo {name} [OPTIONS]") and len(lines) <= 8
    assert f"Try 'zedo {name} --help'" in lines[-1] and "╭" not in result.stderr


def test_the_older_out_spelling_still_works_and_folders_are_made(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json", n=2)
    for flag, name in (("--output", "a/b/new.zedo.json"), ("--out", "old.zedo.json")):
        result = runner.invoke(app, lift_args(tiny_prior_path, str(src), flag, str(tmp_path / name), "-q"))
        assert result.exit_code == 0, result.output
        assert json.loads((tmp_path / name).read_text())["schema"].startswith("zedo.pose3d")
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "--output-dir", str(tmp_path / "x" / "y"), "-q"))
    assert result.exit_code == 0 and (tmp_path / "x" / "y" / "kp.zedo.json").is_file()
    (tmp_path / "file").write_text("")
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "-o", str(tmp_path / "file" / "r.zedo.json")))
    assert result.exit_code == 2 and "is not a folder" in result.stderr


def test_logs_off_a_terminal_are_plain_unwrapped_lines(tiny_prior_path: Path, tmp_path: Path) -> None:
    deep = tmp_path / ("a-rather-long-folder-name-" * 4) / "inputs"
    deep.mkdir(parents=True)
    good = write_coco(deep / "good.json", n=1)
    bad = deep / "bad.json"
    bad.write_text('{"x": 1}')
    args = ["lift", "--prior", str(tiny_prior_path), "--steps", "30", str(good), str(bad)]
    result = runner.invoke(app, [*args, "--output-dir", str(tmp_path / "out")])
    assert result.exit_code == 4
    lines = result.stderr.splitlines()
    assert not any(line != line.rstrip() for line in lines)  # nothing padded
    assert not any(c in result.stderr for c in "╭│┃━")  # no box drawing in a log
    rows = [line for line in lines if line.startswith(str(deep))]
    assert len(rows) == 2 and "failed, exit code 3" in rows[1]  # full paths, never folded
    assert sum(str(bad) in line for line in lines) == 2  # its error once, its summary row once
    assert "1 instance " in result.stderr or "1/1 instance" in result.stderr  # right plurals


def test_figures_go_to_a_json_file_with_o(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json", n=2)
    lifted = tmp_path / "kp.zedo.json"
    assert runner.invoke(app, lift_args(tiny_prior_path, str(src), "-q")).exit_code == 0
    doc = json.loads(lifted.read_text())
    poses = np.array([f["persons"][0]["keypoints_3d"] for f in doc["frames"]], dtype=float)
    gt = tmp_path / "gt.npz"
    np.savez(gt, poses=poses, joint_names=np.array(doc["skeleton"]["joints"]),
             names=np.array([f["file_name"] for f in doc["frames"]]))  # fmt: skip
    out = tmp_path / "scores" / "s.json"
    evaluate = ["evaluate", str(lifted), "--gt", str(gt)]
    result = runner.invoke(app, [*evaluate, "-o", str(out)])
    assert result.exit_code == 0, result.output
    assert json.loads(out.read_text())["mpjpe_mm"] == 0.0 and "MPJPE" in result.stdout
    result = runner.invoke(app, [*evaluate, "-o", str(out)])
    assert result.exit_code == 2 and "--overwrite" in result.stderr
    result = runner.invoke(app, [*evaluate, "-o", "s.txt"])
    assert result.exit_code == 2 and ".json" in result.stderr
    result = runner.invoke(app, [*evaluate, "-o", "-"])
    assert result.exit_code == 0 and json.loads(result.stdout)["count"] == 2


def test_zedo_alone_lists_the_commands_in_the_same_layout() -> None:
    result = runner.invoke(app, [], env={"COLUMNS": "80"}, terminal_width=80)
    assert result.exit_code == 2
    lines = result.stdout.splitlines()
    assert lines[0] == "Usage: zedo [OPTIONS] COMMAND [ARGS]..." and "--version" in result.stdout
    assert all(name in result.stdout for name in COMMANDS)
    assert all(len(line) <= 80 and line == line.rstrip() for line in lines)


def test_a_long_example_is_continued_so_that_it_still_pastes_into_a_shell() -> None:
    example = ("zedo fit-prior --syrip-dir ../shared/data/syrip --split train --recipe "
               "weights_spec/syrip12-scratch.toml -o my.safetensors")  # fmt: skip
    result = runner.invoke(app, ["fit-prior", "--help"], env={"COLUMNS": "80"}, terminal_width=80)
    text = result.stdout
    assert example not in text  # too long for 80 columns: continued with a backslash
    assert " ".join(text.replace(" \\\n", " ").split()).count(example) == 1
