"""Every `wrote ...` line names files that exist: `--person all -o kick.trc`
writes kick_P1.trc and kick_P2.trc, and says so; a CSV names its sidecar; analyze its outputs."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from export_fixtures import write_two_people
from typer.testing import CliRunner

from zedo_cli.cli import app

runner = CliRunner()


def wrote(stderr: str) -> list[Path]:
    """The files of every `wrote a, b` on stderr (at a line's end, after `; ` or at its start)."""
    files = []
    for match in re.finditer(r"(?:^|; )wrote (.+)$", stderr, flags=re.MULTILINE):
        files += [Path(name) for name in match.group(1).split(", ")]
    return files


@pytest.mark.parametrize(
    ("name", "expected"),
    [
        ("kick.trc", ["kick_P1.trc", "kick_P2.trc"]),
        ("kick.c3d", ["kick_P1.c3d", "kick_P2.c3d"]),
        ("kick.csv", ["kick.csv", "kick.meta.json"]),
        ("kick.npz", ["kick.npz"]),
    ],
)
def test_lift_names_every_file_it_wrote(tiny_prior_path: Path, tmp_path: Path, name: str, expected: list[str]) -> None:
    src = write_two_people(tmp_path / "kick.jsonl")
    out = tmp_path / "out" / name
    result = runner.invoke(app, ["lift", str(src), "--prior", str(tiny_prior_path), "--steps", "5", "--person", "all",
                                 "--fps", "30", "-o", str(out)])  # fmt: skip
    assert result.exit_code == 0, result.output
    assert wrote(result.stderr) == [out.with_name(n) for n in expected], result.stderr
    assert sorted(p.name for p in out.parent.iterdir()) == sorted(expected)  # and nothing else
    table = result.stderr[result.stderr.index("zedo lift: 1 input") :] if "zedo lift: 1 input" in result.stderr else ""
    assert not table or all(n in table for n in expected)


def test_analyze_names_what_it_wrote(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_two_people(tmp_path / "kick.jsonl")
    lifted = runner.invoke(app, ["lift", str(src), "--prior", str(tiny_prior_path), "--steps", "5", "-q", "--fps",
                                 "30", "-o", str(tmp_path / "kick.zedo.json")])  # fmt: skip
    assert lifted.exit_code == 0, lifted.output
    result = runner.invoke(app, ["analyze", str(tmp_path / "kick.zedo.json"), "--output-dir", str(tmp_path / "a")])
    assert result.exit_code == 0, result.output
    files = wrote(result.stderr)
    assert [f.name for f in files] == ["kick.analysis.csv", "kick.analysis.json"] and all(f.is_file() for f in files)
