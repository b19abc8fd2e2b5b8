"""`zedo lift` on several inputs, people per frame, output formats and plots."""

from __future__ import annotations

import json
from pathlib import Path

from format_fixtures import BODY25_POSE
from test_cli import lift_args, runner, write_coco

from zedo_cli.cli import app
from zedo_cli.cli.lift import FileOutcome, batch_exit_code
from zedo_cli.errors import ConfigError, InputFormatError


def test_batch_writes_each_output_and_isolates_failures(tiny_prior_path: Path, tmp_path: Path) -> None:
    a, b = write_coco(tmp_path / "a.json"), write_coco(tmp_path / "b.json", n=2)
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    result = runner.invoke(app, [*lift_args(tiny_prior_path, str(a), str(bad), str(b)), "--output-dir", str(out_dir)])
    assert result.exit_code == 4, result.output  # partial success
    assert sorted(p.name for p in out_dir.iterdir()) == ["a.zedo.json", "b.zedo.json"]
    assert "bad.json" in result.output and "invalid JSON" in result.output
    assert json.loads((out_dir / "b.zedo.json").read_text())["summary"]["instances_lifted"] == 2


def test_a_folder_and_a_quoted_glob_expand_to_their_files(tiny_prior_path: Path, tmp_path: Path) -> None:
    folder = tmp_path / "clips"
    folder.mkdir()
    write_coco(folder / "c1.json")
    write_coco(folder / "c2.json")
    result = runner.invoke(app, lift_args(tiny_prior_path, str(folder)))
    assert result.exit_code == 0, result.output
    assert (folder / "c1.zedo.json").is_file() and (folder / "c2.zedo.json").is_file()
    # a re-run must not take the outputs for inputs, and must not overwrite them
    again = runner.invoke(app, lift_args(tiny_prior_path, str(folder / "c*.json")))
    assert again.exit_code == 2 and "already exist" in again.output


def test_existing_outputs_stop_the_batch_before_any_work(tiny_prior_path: Path, tmp_path: Path) -> None:
    a, b = write_coco(tmp_path / "a.json"), write_coco(tmp_path / "b.json")
    (tmp_path / "b.zedo.json").write_text("keep me")
    result = runner.invoke(app, lift_args(tiny_prior_path, str(a), str(b)))
    assert result.exit_code == 2 and "--overwrite" in result.output
    assert not (tmp_path / "a.zedo.json").exists() and (tmp_path / "b.zedo.json").read_text() == "keep me"


def test_one_out_for_many_inputs_is_a_usage_error(tiny_prior_path: Path, tmp_path: Path) -> None:
    a, b = write_coco(tmp_path / "a.json"), write_coco(tmp_path / "b.json")
    result = runner.invoke(app, [*lift_args(tiny_prior_path, str(a), str(b)), "-o", str(tmp_path / "x.json")])
    assert result.exit_code == 2 and "--output-dir" in result.output


def test_missing_input_and_empty_pattern_are_input_errors(tiny_prior_path: Path, tmp_path: Path) -> None:
    for arg in (str(tmp_path / "nope.json"), str(tmp_path / "*.json")):
        result = runner.invoke(app, lift_args(tiny_prior_path, arg))
        assert result.exit_code == 3 and "nope.json" in result.output or "no file matches" in result.output


def test_csv_in_millimetres_root_frame(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json")
    result = runner.invoke(app, [*lift_args(tiny_prior_path, str(src)), "--output-format", "csv", "--units", "mm",
                                 "--frame", "root"])  # fmt: skip
    assert result.exit_code == 0, result.output
    header = (tmp_path / "kp.zedo.csv").read_text().splitlines()[0]
    assert "x_root_mm" in header
    meta = json.loads((tmp_path / "kp.zedo.meta.json").read_text())
    assert meta["units"] == "mm"


def test_stdin_to_stdout_pipeline(tiny_prior_path: Path, tmp_path: Path) -> None:
    text = write_coco(tmp_path / "kp.json").read_text()
    result = runner.invoke(app, lift_args(tiny_prior_path, "-"), input=text)
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    assert doc["summary"]["instances_lifted"] == 3 and doc["input"]["sha256"] is None


def test_person_modes_keep_one_or_all(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json", n=2)
    doc = json.loads(src.read_text())
    for ann in doc["annotations"]:
        ann["image_id"] = 10  # two people in one image
    src.write_text(json.dumps(doc))
    one = runner.invoke(app, [*lift_args(tiny_prior_path, str(src)), "-o", "-"])
    both = runner.invoke(app, [*lift_args(tiny_prior_path, str(src)), "-o", "-", "--person", "all"])
    assert one.exit_code == both.exit_code == 0, one.output + both.output
    assert json.loads(one.stdout)["summary"]["instances_lifted"] == 1
    assert json.loads(both.stdout)["summary"]["instances_lifted"] == 2
    assert json.loads(both.stdout)["params"]["person"] == "all"


def test_plot_writes_pngs(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json")
    result = runner.invoke(app, [*lift_args(tiny_prior_path, str(src)), "--plot", str(tmp_path / "plots")])
    assert result.exit_code == 0, result.output
    pngs = sorted((tmp_path / "plots").glob("kp.*.png"))
    assert [p.name for p in pngs] == ["kp.first.png", "kp.median.png", "kp.worst.png"]
    assert all(p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" for p in pngs)


def test_batch_exit_codes() -> None:
    ok = FileOutcome("a", "a.out")
    bad_input = FileOutcome("b", "b.out", error=InputFormatError("b: bad"))
    bad_usage = FileOutcome("c", "c.out", error=ConfigError("c: bad"))
    assert batch_exit_code([ok, ok]) == 0
    assert batch_exit_code([ok, bad_input]) == 4
    assert batch_exit_code([bad_input, bad_input]) == 3
    assert batch_exit_code([bad_input, bad_usage]) == 4  # mixed failure codes: 4, the table says which


def test_missing_image_size_names_the_input(tiny_prior_path: Path, tmp_path: Path) -> None:
    points = [v for x, y in BODY25_POSE for v in (x, y, 0.9)]  # a BODY_25 person (25 joints on a line: undecidable)
    frame = {"version": 1.3, "people": [{"pose_keypoints_2d": points}]}
    src = tmp_path / "op_000000000000_keypoints.json"
    src.write_text(json.dumps(frame))
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src)))
    # The input lacks what lifting needs (an image size for the principal point): exit 3, as for
    # any input that cannot work, naming the input and the options that would supply it.
    assert result.exit_code == 3 and "op_000000000000_keypoints.json" in result.output
    assert "--image-size" in result.output
