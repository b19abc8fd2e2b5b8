"""A newcomer at the command line: a batch reports and skips an input its up-front check refuses (a
symbolic link loop in a folder: exit 4, the good file written), an --image-size that fills no
image's size is said, `zedo evaluate` on hostile or incomplete results ends in one line, and
`zedo --help` lists the analysts' commands first."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from test_cli import lift_args, runner, write_coco

from zedo_cli.cli import COMMANDS, PANELS, RESEARCH_PANEL, app
from zedo_cli.data.skeleton import get_skeleton


def _errors(output: str) -> list[str]:
    return [line for line in output.splitlines() if line.startswith("zedo: error:")]


def test_a_folder_with_a_good_file_and_a_link_loop_lifts_the_good_one_and_exits_4(
    tiny_prior_path: Path, tmp_path: Path
) -> None:
    folder = tmp_path / "in"
    folder.mkdir()
    write_coco(folder / "good.json")
    (folder / "loop.json").symlink_to("loop.json")  # points at itself
    result = runner.invoke(app, lift_args(tiny_prior_path, str(folder), "--output-dir", str(tmp_path / "out")))
    assert result.exit_code == 4, result.output
    assert _errors(result.output) == [f"zedo: error: {folder / 'loop.json'}: symbolic link loop (too many levels of "
                                      "symbolic links)"]  # fmt: skip
    assert json.loads((tmp_path / "out" / "good.zedo.json").read_text())["summary"]["instances_lifted"] == 3
    alone = runner.invoke(app, lift_args(tiny_prior_path, str(folder / "loop.json"), "-o", str(tmp_path / "x.json")))
    assert alone.exit_code == 3 and len(_errors(alone.output)) == 1  # one input: its error is the command's


def _results_file(coco: Path, out: Path) -> Path:
    doc = json.loads(coco.read_text())
    out.write_text(json.dumps([{"image_id": a["image_id"], "category_id": 1, "keypoints": a["keypoints"],
                                "score": 0.9} for a in doc["annotations"]]))  # fmt: skip
    return out


def _image_sizes(result: Path) -> set[tuple[int, int]]:
    doc = json.loads(result.read_text())
    return {tuple(f["camera"]["image_size"]) for f in doc["frames"]}


def test_an_image_size_that_fills_no_image_is_said(tiny_prior_path: Path, tmp_path: Path) -> None:
    coco = write_coco(tmp_path / "gt.json")  # images[] state 640x480
    results = _results_file(coco, tmp_path / "det.json")
    out = tmp_path / "r.zedo.json"
    args = [str(results), "--images", str(coco), "--image-size", "800", "600", "-o", str(out)]
    done = runner.invoke(app, lift_args(tiny_prior_path, *args))
    assert done.exit_code == 0, done.output
    warning = [line for line in done.output.splitlines() if line.startswith("zedo: warning:")]
    assert warning == [f"zedo: warning: {results}: --image-size 800 600 is not used: the input or --images {coco} "
                       "states every image's size (--image-size fills only the sizes that the input and --images "
                       "leave unknown)"]  # fmt: skip
    assert _image_sizes(out) == {(640, 480)}
    doc = json.loads(coco.read_text())  # images[] without sizes: --image-size fills them, silently
    for image in doc["images"]:
        del image["width"], image["height"]
    coco.write_text(json.dumps(doc))
    done = runner.invoke(app, lift_args(tiny_prior_path, *args, "--overwrite"))
    assert done.exit_code == 0 and "zedo: warning:" not in done.output, done.output
    assert _image_sizes(out) == {(800, 600)}


def _lifted(tiny_prior_path: Path, tmp_path: Path) -> tuple[Path, Path]:
    src = write_coco(tmp_path / "kp.json", n=3)
    out = tmp_path / "r.json"
    assert runner.invoke(app, lift_args(tiny_prior_path, str(src), "-o", str(out))).exit_code == 0
    gt = tmp_path / "gt.npz"
    doc = json.loads(out.read_text())
    poses = np.array([f["persons"][0]["keypoints_3d"] for f in doc["frames"]], dtype=float)
    np.savez(gt, poses=poses, joint_names=np.array(get_skeleton("syrip12").joints),
             names=np.array([f"img{i}.jpg" for i in range(3)]))  # fmt: skip
    return out, gt


def test_evaluate_json_on_a_result_with_a_null_joint_is_one_line_and_never_nan(
    tiny_prior_path: Path, tmp_path: Path
) -> None:
    out, gt = _lifted(tiny_prior_path, tmp_path)
    doc = json.loads(out.read_text())
    doc["frames"][1]["persons"][0]["keypoints_3d"][4] = [None, None, None]
    out.write_text(json.dumps(doc))
    result = runner.invoke(app, ["evaluate", str(out), "--gt", str(gt), "--json"])
    assert "NaN" not in result.stdout and "Traceback" not in result.output
    assert result.exit_code == 3, result.output
    expected = (f"zedo: error: {out}: pose img1.jpg: joint left_knee is null or missing "
                "(protocol syrip12 needs every syrip12 joint; 1 of 3 poses lack one)")  # fmt: skip
    assert _errors(result.output) == [expected]


@pytest.mark.parametrize(
    ("hostile", "said"),
    [("[" * 100_000 + "]" * 100_000, "nested too deeply to read"), ("9" * 5000, "an integer of more than 4300 digits"),
     ('1, "frame_index": 1', "duplicate key 'frame_index' in a JSON object (which value is meant is unknown)")],
)  # fmt: skip
def test_evaluate_and_analyze_refuse_a_hostile_result_in_one_line(
    tiny_prior_path: Path, tmp_path: Path, hostile: str, said: str
) -> None:
    out, gt = _lifted(tiny_prior_path, tmp_path)
    text = out.read_text()
    at = text.index('"frame_index": ') + len('"frame_index": ')
    out.write_text(text[:at] + hostile + text[at + 1 :])
    for args in (["evaluate", str(out), "--gt", str(gt), "--json"], ["analyze", str(out), "-o", "-"]):
        result = runner.invoke(app, args)
        assert result.exit_code == 3, result.output
        assert _errors(result.output) == [f"zedo: error: {out}: {said}" if "duplicate" in said
                                          else f"zedo: error: {out}: invalid JSON: {said}"]  # fmt: skip


def test_help_lists_the_analysts_commands_before_the_research_ones() -> None:
    text = runner.invoke(app, ["--help"]).output
    analysts, research = ("lift", "analyze", "render", "calibrate"), ("fit-prior", "adapt", "augment", "benchmark")
    assert (
        max(text.index(f" {c} ") for c in analysts)
        < text.index(RESEARCH_PANEL)
        < min(text.index(f" {c} ") for c in research)
    )
    assert set(COMMANDS) == {c for panel in PANELS.values() for c in panel}


def test_every_page_gives_a_refused_calibration_its_exit_code() -> None:
    import re

    from zedo_cli.errors import CalibrationError

    root = Path(__file__).resolve().parents[2]
    pages = [root / "README.md", *sorted((root / "docs").glob("*.md")), *sorted((root / "zedo_cli").rglob("*.py"))]
    said = re.compile(r"(calibrat\w*|CalibrationError|board)[^.;]{0,80}?exit code (\d+)", re.IGNORECASE | re.DOTALL)
    found = {(p.name, m.group(2)) for p in pages for m in said.finditer(p.read_text())}
    assert found and {code for _, code in found} == {str(CalibrationError.exit_code)}, found
