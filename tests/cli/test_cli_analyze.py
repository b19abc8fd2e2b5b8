"""`zedo analyze` and `zedo benchmark-symmetry` from the command line: every result format,
stdin and the documented pipe, outputs, and errors as one line with a documented exit code."""

from __future__ import annotations

import csv
import io
import json
import subprocess
import sys
from pathlib import Path

import pytest
from analysis_results import kicking_poses, result_document, write_document
from test_cli import lift_args, write_coco
from typer.testing import CliRunner

from zedo_cli.cli import app

runner = CliRunner()


def rows(text: str) -> list[dict[str, str]]:
    return list(csv.DictReader(io.StringIO(text)))


@pytest.fixture()
def kick(tmp_path: Path) -> Path:
    return write_document(tmp_path / "kick.zedo.json", result_document(kicking_poses(30), fps=30.0))


@pytest.mark.parametrize("fmt", ["json", "jsonl", "csv", "npz"])
def test_lift_then_analyze_every_format(tiny_prior_path: Path, tmp_path: Path, fmt: str) -> None:
    src = write_coco(tmp_path / "kp.json")
    lifted = runner.invoke(app, lift_args(tiny_prior_path, str(src), "--output-format", fmt, "--units", "mm"))
    assert lifted.exit_code == 0, lifted.output
    result = runner.invoke(app, ["analyze", str(tmp_path / f"kp.zedo.{fmt}"), "-q"])
    assert result.exit_code == 0, result.output
    table = rows((tmp_path / "kp.analysis.csv").read_text())
    # per frame: 4 symmetry angles, their bands and probabilities, 12 joint angles, head tilt and turn
    assert len(table) == 3 * (4 + 4 + 4 + 12 + 2) and {r["file_name"] for r in table} == {
        "img0.jpg",
        "img1.jpg",
        "img2.jpg",
    }
    head = [r for r in table if r["measure"].startswith("head_")]  # the face at v = 0: no head, and why
    assert len(head) == 3 * 2 and all(r["value"] == "" and r["interval"] == "none" and r["interval_note"] for r in head)
    doc = json.loads((tmp_path / "kp.analysis.json").read_text())
    assert doc["input"]["format"] == fmt and doc["input"]["units_in_file"] == "mm"
    assert len(doc["rows"]) == len(table)


def test_the_documented_pipe(tiny_prior_path: Path, tmp_path: Path) -> None:
    """`zedo lift kp.json -o - -q | zedo analyze -` in a real shell pipe."""
    src = write_coco(tmp_path / "kp.json", n=2)
    zedo = [sys.executable, "-c", "from zedo_cli.cli import main; main()"]
    lift = subprocess.Popen([*zedo, *lift_args(tiny_prior_path, str(src), "-o", "-")], stdout=subprocess.PIPE)
    done = subprocess.run([*zedo, "analyze", "-", "-q"], stdin=lift.stdout, capture_output=True, text=True, timeout=300)
    assert lift.wait(timeout=300) == 0
    assert done.returncode == 0, done.stderr
    table = rows(done.stdout)
    assert len(table) == 2 * (4 + 4 + 4 + 12 + 2) and table[0]["measure"] == "symmetry_upper_arm_deg"
    assert (table[0]["interval"], table[0]["interval_note"]) == ("none", "no measure calibration for this prior")


def test_stdin_in_jsonl_and_csv_output_choices(tiny_prior_path: Path, tmp_path: Path, kick: Path) -> None:
    src = write_coco(tmp_path / "kp.json", n=2)
    lifted = runner.invoke(app, lift_args(tiny_prior_path, str(src), "-o", "-", "--output-format", "jsonl"))
    assert lifted.exit_code == 0
    result = runner.invoke(app, ["analyze", "-", "--json", "-q"], input=lifted.stdout)
    assert result.exit_code == 0, result.output
    assert json.loads(result.stdout)["input"]["format"] == "jsonl"
    out = tmp_path / "out" / "nested"  # -o makes its folder, as every command does
    for name in ("k.csv", "k.json"):
        result = runner.invoke(app, ["analyze", str(kick), "-o", str(out / name), "-q"])
        assert result.exit_code == 0, result.output
    assert sorted(p.name for p in out.iterdir()) == ["k.csv", "k.json"]
    assert json.loads((out / "k.json").read_text())["input"]["path"] == str(kick)
    assert (out / "k.csv").read_text().startswith("frame_index,")
    result = runner.invoke(app, ["analyze", str(kick), "--csv", str(out / "old.csv"), "-q"])  # the older spelling
    assert result.exit_code == 0 and (out / "old.csv").read_text() == (out / "k.csv").read_text()


def test_summary_report_and_overwrite(kick: Path, tmp_path: Path) -> None:
    report = tmp_path / "report"
    result = runner.invoke(app, ["analyze", str(kick), "--report", str(report), "--symmetry-threshold", "20"])
    assert result.exit_code == 0, result.output
    assert "no calibrated intervals" in result.stderr and "shank" in result.stderr
    page = (report / "kick.report.html").read_text()
    assert "over time" in page and "symmetric at ≤ 20°" in page
    again = runner.invoke(app, ["analyze", str(kick), "--report", str(report)])
    assert again.exit_code == 2 and "already exists" in again.stderr and "--overwrite" in again.stderr
    assert runner.invoke(app, ["analyze", str(kick), "--report", str(report), "--overwrite", "-q"]).exit_code == 0


def test_a_folder_and_several_inputs(kick: Path, tmp_path: Path) -> None:
    write_document(tmp_path / "two.zedo.json", result_document(kicking_poses(3)))
    out = tmp_path / "out"
    out.mkdir()
    result = runner.invoke(app, ["analyze", str(tmp_path), "--output-dir", str(out), "-q"])
    assert result.exit_code == 0, result.output
    assert sorted(p.name for p in out.iterdir()) == [
        "kick.analysis.csv", "kick.analysis.json", "two.analysis.csv", "two.analysis.json",
    ]  # fmt: skip


@pytest.mark.parametrize(
    ("content", "message"),
    [
        ("", "empty file"),
        ('{"images": [], "annotations": [], "categories": []}', "2D keypoints (coco-annotations), not a zedo result"),
        ('{"schema": "other/1", "frames": []}', "schema: expected a zedo result file"),
        ('[{"image_id": 1, "keypoints": [1, 2, 1], "score": 0.9}]', "2D keypoints (coco-results), not a zedo result"),
        ('{"version": 1.3, "people": []}', "2D keypoints (openpose), not a zedo result (3D poses): lift them first"),
        ('{"frame": 0, "persons": []}\n{"frame": 1, "persons": []}\n', "2D keypoints (zedo-jsonl), not a zedo"),
        ("not json at all", "not a zedo result"),
    ],
)
def test_bad_input_is_one_line_and_exit_3(tmp_path: Path, content: str, message: str) -> None:
    bad = tmp_path / "bad.json"
    bad.write_text(content)
    result = runner.invoke(app, ["analyze", str(bad)])
    assert result.exit_code == 3, result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"zedo: error: {bad}") and message in lines[0]
    assert not (tmp_path / "bad.analysis.csv").exists()


def test_a_folder_of_openpose_frames_is_told_to_be_lifted(tmp_path: Path) -> None:
    folder = tmp_path / "frames"
    folder.mkdir()
    for i in range(3):
        (folder / f"clip_{i:012d}_keypoints.json").write_text('{"version": 1.3, "people": []}')
    result = runner.invoke(app, ["analyze", str(folder)])
    assert result.exit_code == 3, result.output
    assert "a folder of OpenPose 2D keypoint frames, not zedo results: lift it first" in result.stderr


def test_a_result_without_the_needed_joints_exits_3(tmp_path: Path) -> None:
    doc = result_document(kicking_poses(2))
    for frame in doc["frames"]:
        frame["persons"][0]["keypoints_3d"] = None  # nothing lifted: no joint to measure
    path = write_document(tmp_path / "none.zedo.json", doc)
    result = runner.invoke(app, ["analyze", str(path)])
    assert result.exit_code == 3 and "no lifted person" in result.stderr
    result = runner.invoke(app, ["analyze", str(tmp_path / "missing.zedo.json")])
    assert result.exit_code == 3 and "file not found" in result.stderr


def test_one_bad_input_of_several_exits_4(kick: Path, tmp_path: Path) -> None:
    bad = tmp_path / "bad.zedo.json"
    bad.write_text("{}")
    result = runner.invoke(app, ["analyze", str(kick), str(bad), "-q"])
    assert result.exit_code == 4 and (tmp_path / "kick.analysis.csv").is_file()
    assert "bad.zedo.json: schema" in result.stderr


def test_usage_errors_exit_2(kick: Path, tmp_path: Path) -> None:
    (tmp_path / "plain").write_text("x")
    for args in (["--symmetry-threshold", "-5"], ["--fps", "0"], ["-o", "-", "--json"], ["-o", "x.txt"],
                 ["--output-dir", str(tmp_path / "plain")], ["-o", "a.csv", "--csv", "b.csv"]):  # fmt: skip
        result = runner.invoke(app, ["analyze", str(kick), *args])
        assert result.exit_code == 2, (args, result.output)
    two = write_document(tmp_path / "two.zedo.json", result_document(kicking_poses(3)))
    result = runner.invoke(app, ["analyze", str(kick), str(two), "-o", "x.csv"])
    assert result.exit_code == 2 and "--output-dir" in result.stderr


def test_help_teaches_with_examples() -> None:
    result = runner.invoke(app, ["analyze", "--help"])
    assert result.exit_code == 0
    for needle in ("symmetry", "calibrat", "zedo lift kp.json -o - -q | zedo analyze -", "--report"):
        assert needle in result.output
    assert "benchmark-symmetry" in runner.invoke(app, ["--help"]).output


def test_benchmark_symmetry_without_data_exits_3(tmp_path: Path) -> None:
    result = runner.invoke(app, ["benchmark-symmetry", "--syrip-dir", str(tmp_path), "-q"])
    assert result.exit_code == 3 and "file not found" in result.stderr
    result = runner.invoke(app, ["benchmark-symmetry", "--syrip-dir", str(tmp_path), "--inputs", "x"])
    assert result.exit_code == 2


def test_evaluate_reads_every_result_format_through_the_shared_reader(tiny_prior_path: Path, tmp_path: Path) -> None:
    import numpy as np
    from helpers import synthetic_poses

    from zedo_cli.data.skeleton import get_skeleton

    src = write_coco(tmp_path / "kp.json", n=3)
    gt = tmp_path / "gt.npz"
    np.savez(gt, poses=synthetic_poses(3, seed=3), joint_names=np.array(get_skeleton("syrip12").joints),
             names=np.array([f"img{i}.jpg" for i in range(3)]))  # fmt: skip
    scores = {}
    for fmt in ("json", "csv", "npz"):
        out = tmp_path / f"r.zedo.{fmt}"
        assert runner.invoke(app, lift_args(tiny_prior_path, str(src), "-o", str(out), "--units", "mm")).exit_code == 0
        result = runner.invoke(app, ["evaluate", str(out), "--gt", str(gt), "--json"])
        assert result.exit_code == 0, result.output
        scores[fmt] = json.loads(result.stdout)["mpjpe_mm"]
    assert scores["csv"] == pytest.approx(scores["json"], abs=0.01) and scores["npz"] == pytest.approx(scores["json"])


def test_a_lift_given_its_focal_length_gets_the_bundled_camera_calibration(tmp_path: Path) -> None:
    """The bundled prior and preset, `--focal 1000` (the camera the 2D was made with, 1 m away): every
    symmetry value gets a calibrated interval from the known cameras' calibration."""
    src = write_coco(tmp_path / "kp.json", n=4)
    out = tmp_path / "kp.zedo.json"
    lifted = runner.invoke(app, ["lift", str(src), "--focal", "1000", "-q", "-o", str(out)])
    assert lifted.exit_code == 0, lifted.output
    result = runner.invoke(app, ["analyze", str(out), "-o", "-", "-q"])
    assert result.exit_code == 0, result.output
    rows = list(csv.DictReader(io.StringIO(result.stdout)))
    sym = [r for r in rows if r["measure"].startswith("symmetry_") and r["measure"].endswith("_deg")]
    assert len(sym) == 16 and {r["interval"] for r in sym} == {"calibrated"}
    assert all(float(r["low"]) <= float(r["value"]) <= float(r["high"]) for r in sym)
    for focal, stand_in in (("3000", False), ("6000", True)):  # 3 m inside the known cameras' range, 6 m beyond it
        far = runner.invoke(app, ["lift", str(src), "--focal", focal, "-q", "-o", str(tmp_path / "far.zedo.json"),
                                  "--overwrite"])  # fmt: skip
        assert far.exit_code == 0, far.output
        table = runner.invoke(app, ["analyze", str(tmp_path / "far.zedo.json"), "-o", "-", "-q"]).stdout
        thigh = [r for r in csv.DictReader(io.StringIO(table)) if r["measure"] == "symmetry_thigh_deg"]
        reasons = {f"{r['interval']}: {r['interval_note']}".removesuffix(": ") for r in thigh}
        # outside the range the pseudo camera's calibration stands in, as without --focal
        assert "calibrated" in reasons and not any(x.startswith("none: camera outside") for x in reasons)
        doc = json.loads(runner.invoke(app, ["analyze", str(tmp_path / "far.zedo.json"), "--json", "-q"]).stdout)
        assert any("the pseudo camera's calibration stands in" in n for n in doc["notes"]) == stand_in, focal
