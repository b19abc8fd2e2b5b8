"""A batch of inputs: one bad input never sinks the batch, and nothing is lost or overwritten."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from test_cli import lift_args, runner, write_coco

import zedo_cli.pipeline.lift as lift_module  # the per-input steps zedo lift runs
from zedo_cli.cli import app


def _degenerate(path: Path) -> Path:
    """A COCO file whose every person has all joints at the image centre (the principal point)."""
    write_coco(path, n=2)
    doc = json.loads(path.read_text())
    for ann in doc["annotations"]:
        kp = ann["keypoints"]
        for j in range(17):
            if kp[3 * j + 2] > 0:
                kp[3 * j : 3 * j + 2] = [320.0, 240.0]
    path.write_text(json.dumps(doc))
    return path


def test_good_degenerate_good_lifts_both_good_files_and_exits_4(tiny_prior_path: Path, tmp_path: Path) -> None:
    folder = tmp_path / "clips"
    folder.mkdir()
    write_coco(folder / "a.json")
    _degenerate(folder / "b.json")
    write_coco(folder / "c.json")
    result = runner.invoke(app, lift_args(tiny_prior_path, str(folder)))
    assert result.exit_code == 4, result.output
    assert (folder / "a.zedo.json").is_file() and (folder / "c.zedo.json").is_file()
    assert not (folder / "b.zedo.json").exists()
    errors = [line for line in result.output.splitlines() if line.startswith("zedo: error:")]
    assert len(errors) == 1 and "b.json" in errors[0] and "degenerate_geometry" in errors[0]


def test_any_exception_of_one_input_is_isolated(
    tiny_prior_path: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    a, b, c = (write_coco(tmp_path / f"{n}.json") for n in "abc")
    real = lift_module.read_selected

    def flaky(source: str, *args: object) -> object:
        if source == str(b):
            raise RuntimeError("boom\nsecond line")
        return real(source, *args)  # type: ignore[arg-type]

    monkeypatch.setattr(lift_module, "read_selected", flaky)
    result = runner.invoke(app, lift_args(tiny_prior_path, str(a), str(b), str(c)))
    assert result.exit_code == 4, result.output
    assert (tmp_path / "a.zedo.json").is_file() and (tmp_path / "c.zedo.json").is_file()
    assert f"zedo: error: {b}: internal error: RuntimeError: boom\\nsecond line" in result.output


def test_names_that_look_like_markup_are_shown_as_they_are(
    tiny_prior_path: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)  # short relative names: the table does not wrap them
    write_coco(tmp_path / "good.json")
    (tmp_path / "[bold]bad.json").write_text("[1, [2]")
    args = [a for a in lift_args(tiny_prior_path, "good.json", "[bold]bad.json") if a != "-q"]  # -q: no table
    result = runner.invoke(app, args)
    assert result.exit_code == 4, result.output
    table = result.output[result.output.index("zedo lift: 2 inputs") :]
    assert "[bold]bad.json" in table and "Traceback" not in result.output


def test_output_equal_to_the_input_is_refused_even_with_overwrite(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json")
    before = src.read_text()
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "-o", str(src), "--overwrite"))
    assert result.exit_code == 2, result.output
    assert "is an input of this run" in result.output and src.read_text() == before
    link = tmp_path / "link.json"
    link.symlink_to(src)
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "-o", str(link), "--overwrite"))
    assert result.exit_code == 2 and src.read_text() == before, result.output


def test_an_output_named_like_another_input_is_refused(tiny_prior_path: Path, tmp_path: Path) -> None:
    a = write_coco(tmp_path / "a.json")
    other = write_coco(tmp_path / "a.zedo.json")  # a's default output name, given as an input
    before = other.read_text()
    result = runner.invoke(app, lift_args(tiny_prior_path, str(a), str(other), "--overwrite"))
    assert result.exit_code == 2 and "is an input of this run" in result.output, result.output
    assert other.read_text() == before
    # A CSV output's sidecar counts too.
    meta = write_coco(tmp_path / "res.meta.json")
    result = runner.invoke(app, lift_args(tiny_prior_path, str(meta), "-o", str(tmp_path / "res.csv"), "--overwrite"))
    assert result.exit_code == 2 and "res.meta.json" in result.output, result.output


def test_plot_collisions_are_refused_before_any_result_is_written(tiny_prior_path: Path, tmp_path: Path) -> None:
    d1, d2, plots = tmp_path / "d1", tmp_path / "d2", tmp_path / "plots"
    d1.mkdir()
    d2.mkdir()
    a, b = write_coco(d1 / "kp.json"), write_coco(d2 / "kp.json")  # the same plot prefix "kp"
    result = runner.invoke(app, lift_args(tiny_prior_path, str(a), str(b), "--plot", str(plots), "--overwrite"))
    assert result.exit_code == 2 and "would both be plotted" in result.output, result.output
    assert not (d1 / "kp.zedo.json").exists() and not (d2 / "kp.zedo.json").exists()
    # An existing plot without --overwrite: refused before the result is written.
    plots.mkdir()
    (plots / "kp.worst.png").write_bytes(b"mine")
    result = runner.invoke(app, lift_args(tiny_prior_path, str(a), "--plot", str(plots)))
    assert result.exit_code == 2 and "kp.worst.png" in result.output, result.output
    assert not (d1 / "kp.zedo.json").exists() and (plots / "kp.worst.png").read_bytes() == b"mine"
    # A plot folder that is a file.
    result = runner.invoke(app, lift_args(tiny_prior_path, str(a), "--plot", str(a)))
    assert result.exit_code == 2 and "not a folder" in result.output, result.output
