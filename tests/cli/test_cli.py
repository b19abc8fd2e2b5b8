"""CLI tests: each command's main path, and errors as one line with a documented exit code."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from helpers import K_TEST, project_poses, synthetic_poses, write_coco  # noqa: F401 (tests/cli import it from here)
from typer.testing import CliRunner

from zedo_cli.cli import app
from zedo_cli.data.skeleton import get_skeleton

runner = CliRunner()


def lift_args(prior: Path, *extra: str) -> list[str]:
    return ["lift", "--prior", str(prior), "--steps", "30", "-q", *extra]


def test_help_lists_commands_and_exit_codes() -> None:
    result = runner.invoke(app, ["--help"])
    assert result.exit_code == 0
    for word in ("lift", "fit-prior", "evaluate", "benchmark", "Exit codes"):
        assert word in result.output


def test_lift_writes_the_documented_json(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json", drop_joint=2)
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "--focal", "1000"))
    assert result.exit_code == 0, result.output
    doc = json.loads((tmp_path / "kp.zedo.json").read_text())
    assert doc["schema"] == "zedo.pose3d/1" and doc["units"] == "m" and doc["coordinate_frame"] == "camera"
    assert doc["skeleton"]["name"] == "syrip12" and len(doc["skeleton"]["joints"]) == 12
    assert doc["params"]["preset"] == "fast" and doc["params"]["steps"] == 30  # the default preset
    assert len(doc["params"]["prior"]["sha256"]) == 64
    frame = doc["frames"][0]
    assert frame["image_id"] == 10 and frame["file_name"] == "img0.jpg"
    assert frame["camera"]["K"] == [[1000.0, 0.0, 320.0], [0.0, 1000.0, 240.0], [0.0, 0.0, 1.0]]
    assert frame["camera"]["source"] == "cli"
    person = frame["persons"][0]
    assert len(person["keypoints_3d"]) == 12 and person["observed"][2] is False
    assert person["reprojection_error_px"][2] is None and person["keypoints_2d"][2] is None
    assert any("right_ankle" in f for f in person["flags"])
    assert doc["summary"]["instances_lifted"] == 3


def test_lift_to_stdout_and_same_output_for_same_seed(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json", n=2)
    first = runner.invoke(app, lift_args(tiny_prior_path, str(src), "-o", "-"))
    second = runner.invoke(app, lift_args(tiny_prior_path, str(src), "-o", "-"))
    assert first.exit_code == 0
    a, b = json.loads(first.stdout), json.loads(second.stdout)
    assert a["frames"] == b["frames"]
    assert a["camera"]["source"] == "pseudo"


def test_lift_never_overwrites_without_asking(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json", n=1)
    out = tmp_path / "out.json"
    out.write_text("precious")
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "-o", str(out)))
    assert result.exit_code == 2 and "--overwrite" in result.output
    assert out.read_text() == "precious"
    assert runner.invoke(app, lift_args(tiny_prior_path, str(src), "-o", str(out), "--overwrite")).exit_code == 0


@pytest.mark.parametrize(
    ("content", "extra", "code", "needle"),
    [
        (None, [], 3, "file not found"),
        ("{not json", [], 3, "invalid JSON"),
        ('{"images": [], "annotations": [], "categories": []}', [], 3, "no instances"),
        (
            json.dumps([{"image_id": 1, "keypoints": [1, 2, 1] * 14, "score": 1}]),
            ["--image-size", "640", "480"],
            3,
            "joint count",
        ),
        ("coco", ["--focal", "0"], 2, "--focal"),
        ("coco", ["--focal", "-5"], 2, "--focal"),
        ("coco", ["--min-confidence", "2"], 2, "--min-confidence"),
        ("coco", ["--preset", "nope"], 2, "--preset must be one of faithful, fast, fast-bf16, fast-fp32"),
        (json.dumps([{"image_id": 1, "keypoints": [1, 2, 1] * 17, "score": 1}]), [], 3, "image size"),
        (
            json.dumps([{"image_id": 1, "keypoints": [0, 0, 0] * 17, "score": 1}]),
            ["--image-size", "640", "480"],
            3,
            "no instance has 3 or more observed",
        ),
    ],
)
def test_lift_errors_are_one_line_with_exit_code(
    tiny_prior_path: Path, tmp_path: Path, content: str | None, extra: list[str], code: int, needle: str
) -> None:
    src = tmp_path / "kp.json"
    if content == "coco":
        write_coco(src, n=1)
    elif content is not None:
        src.write_text(content)
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), *extra))
    assert result.exit_code == code, result.output
    assert needle in result.output and "Traceback" not in result.output
    assert result.output.strip().startswith("zedo: error:")


def test_lift_with_a_prior_of_another_format_is_an_error(tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json", n=1)
    bad = tmp_path / "bad.safetensors"
    bad.write_bytes(b"junk")
    result = runner.invoke(app, ["lift", str(src), "--prior", str(bad)])
    assert result.exit_code == 3 and "not a readable safetensors file" in result.output


def test_fit_prior_then_lift_with_it(tmp_path: Path) -> None:
    poses = synthetic_poses(40, seed=5)
    npz = tmp_path / "poses.npz"
    np.savez(npz, poses=poses, joint_names=np.array(get_skeleton("syrip12").joints))
    out = tmp_path / "p.safetensors"
    args = ["fit-prior", str(npz), "--epochs", "2", "--batch-size", "20", "--seed", "3", "-q", "--out", str(out)]
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    assert runner.invoke(app, args).exit_code == 2  # exists: not overwritten
    from zedo_cli.prior.weights import load_prior

    prior = load_prior(out)
    assert prior.metadata["training"]["steps"] == 4 and prior.metadata["training"]["seed"] == 3
    assert prior.metadata["data"]["count"] == 40


@pytest.mark.parametrize(
    ("args", "code", "needle"),
    [
        (["fit-prior", "missing.npz", "--out", "{tmp}/p.safetensors"], 3, "file not found"),
        (["fit-prior", "--out", "{tmp}/p.safetensors"], 2, "exactly one source"),
        (["fit-prior", "{tmp}/bad.npz", "--out", "{tmp}/p.safetensors"], 3, "not a readable npz"),
        (["fit-prior", "{tmp}/ok.npz", "--epochs", "0", "--out", "{tmp}/p.safetensors"], 2, "epochs"),
        (["fit-prior", "{tmp}/ok.npz", "--recipe", "{tmp}/r.toml", "--out", "{tmp}/p.safetensors"], 2, "unknown keys"),
    ],
)
def test_fit_prior_errors(tmp_path: Path, args: list[str], code: int, needle: str) -> None:
    (tmp_path / "bad.npz").write_text("nope")
    np.savez(tmp_path / "ok.npz", poses=synthetic_poses(4, 0), joint_names=np.array(get_skeleton("syrip12").joints))
    (tmp_path / "r.toml").write_text("[training]\nepochz = 3\n")
    result = runner.invoke(app, [a.replace("{tmp}", str(tmp_path)) for a in args])
    assert result.exit_code == code, result.output
    assert needle in result.output and "Traceback" not in result.output


def test_evaluate_scores_a_result_against_npz_truth(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json", n=3)
    out = tmp_path / "r.json"
    assert runner.invoke(app, lift_args(tiny_prior_path, str(src), "-o", str(out), "--focal", "1000")).exit_code == 0
    truth = synthetic_poses(3, seed=3)
    gt = tmp_path / "gt.npz"
    np.savez(gt, poses=truth, joint_names=np.array(get_skeleton("syrip12").joints),
             names=np.array([f"img{i}.jpg" for i in range(3)]))  # fmt: skip
    result = runner.invoke(app, ["evaluate", str(out), "--gt", str(gt), "--json"])
    assert result.exit_code == 0, result.output
    scores = json.loads(result.stdout)
    assert scores["count"] == 3 and 0 < scores["pa_mpjpe_mm"] <= scores["mpjpe_mm"] < 60
    assert set(scores["per_joint_mpjpe_mm"]) == set(get_skeleton("syrip12").joints)


def test_evaluate_scores_lifted_persons_and_counts_the_ground_truth_left_unscored(
    tiny_prior_path: Path, tmp_path: Path
) -> None:
    src = write_coco(tmp_path / "kp.json", n=3)
    doc = json.loads(src.read_text())
    kp = np.array(doc["annotations"][2]["keypoints"]).reshape(17, 3)
    kp[np.flatnonzero(kp[:, 2] > 0)[2:]] = 0  # two joints left: too few to lift
    doc["annotations"][2]["keypoints"] = kp.ravel().tolist()
    src.write_text(json.dumps(doc))
    out = tmp_path / "r.json"
    assert runner.invoke(app, lift_args(tiny_prior_path, str(src), "-o", str(out))).exit_code == 0
    names = np.array([f"img{i}.jpg" for i in range(3)])
    joints = np.array(get_skeleton("syrip12").joints)
    np.savez(tmp_path / "gt3.npz", poses=synthetic_poses(3, seed=3), joint_names=joints, names=names)
    np.savez(tmp_path / "gt2.npz", poses=synthetic_poses(3, seed=3)[:2], joint_names=joints, names=names[:2])
    scores = {}
    for gt in ("gt3", "gt2"):
        result = runner.invoke(app, ["evaluate", str(out), "--gt", str(tmp_path / f"{gt}.npz"), "--json"])
        assert result.exit_code == 0 and "Traceback" not in result.output, result.output
        scores[gt] = json.loads(result.stdout)
    assert scores["gt3"]["count"] == scores["gt2"]["count"] == 2
    assert (scores["gt3"]["ground_truth_without_prediction"], scores["gt2"]["ground_truth_without_prediction"]) == (
        1,
        0,
    )
    for key in ("mpjpe_mm", "pa_mpjpe_mm"):  # the person not lifted is counted, not scored
        assert scores["gt3"][key] == scores["gt2"][key] and np.isfinite(scores["gt3"][key])
    table = runner.invoke(app, ["evaluate", str(out), "--gt", str(tmp_path / "gt3.npz")])
    assert table.exit_code == 0 and "1 ground-truth poses have no lifted prediction" in " ".join(table.output.split())


def test_evaluate_errors(tmp_path: Path) -> None:
    bad = tmp_path / "r.json"
    bad.write_text(json.dumps({"schema": "other"}))
    result = runner.invoke(app, ["evaluate", str(bad), "--gt", str(bad)])
    assert result.exit_code == 3
    result = runner.invoke(app, ["evaluate", str(bad)])
    assert result.exit_code == 2 and "--syrip-dir or --gt" in result.output


def test_k_matrix_is_used(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json", n=1)
    kfile = tmp_path / "K.json"
    kfile.write_text(json.dumps({"K": K_TEST.tolist()}))
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "--intrinsics", str(kfile), "-o", "-"))
    assert result.exit_code == 0, result.output
    frame = json.loads(result.stdout)["frames"][0]
    assert frame["camera"]["source"] == "file" and frame["camera"]["K"][0][0] == 1000.0


def test_line_progress_prints_plain_lines_only_after_the_interval(capsys) -> None:
    from zedo_cli.cli.common import LineProgress

    quiet_now = LineProgress(interval=3600.0)
    task = quiet_now.add_task("fit", total=10, status="")
    quiet_now.update(task, completed=5, status="loss 1.0")
    assert capsys.readouterr().err == ""
    every_call = LineProgress(interval=0.0)
    task = every_call.add_task("fit", total=10, status="")
    every_call.update(task, completed=5, status="loss 1.0")
    assert "fit: 5/10 loss 1.0" in capsys.readouterr().err


def test_benchmark_table_says_how_many_poses_were_not_lifted() -> None:
    from rich.console import Console

    from zedo_cli.cli.evaluate import _benchmark_table
    from zedo_cli.evaluation.syrip_benchmark import Score

    scores = [("p / fast", Score("gt", 100, 40.0, 26.0, {}, 1.0, 100.0, 0.1, 0.0, 16.0, 0.9, 2)),
              ("p / fast", Score("detected", 100, 44.0, 27.0, {}, 1.0, 100.0, 0.1, 0.0, 17.0, 0.9))]  # fmt: skip
    console = Console(record=True, width=250)
    console.print(_benchmark_table(scores))
    text = console.export_text()
    assert "100 (2 not lifted, not scored)" in text and text.count("not lifted") == 1
