"""`zedo lift` on hand annotations (LabelMe folders and files, Label Studio exports): each joint
lands on the keypoint of the same name, the other points are kept, bad files are one line, exit 3."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from annotation_fixtures import (
    NYCU_LABELS,
    labelme_doc,
    labelme_folder,
    labelme_shape,
    ls_result,
    ls_task,
    nycu_label_studio_results,
    pose_pixels,
    write_json,
)
from test_cli import runner

from zedo_cli.cli import app


def _lift(src: Path, prior: Path, *extra: str) -> tuple[int, str, str]:
    args = ["lift", str(src), "--prior", str(prior), "--preset", "faithful", "--steps", "10", "-o", "-", *extra]
    result = runner.invoke(app, args)
    return result.exit_code, result.stdout, result.stderr


@pytest.mark.parametrize("temporal", [False, True])
def test_a_labelme_folder_lifts_with_each_joint_on_its_name(tiny_prior_path: Path, tmp_path: Path, temporal: bool):
    folder = labelme_folder(tmp_path / "infant01", [1, 2, 3, 4])
    doc_of = json.loads((folder / "img_1.json").read_text())
    doc_of["shapes"].append(labelme_shape("Pacifier", 300.0, 150.0))
    write_json(folder / "img_1.json", doc_of)
    extra = ("--temporal", "smooth") if temporal else ()
    code, out, err = _lift(folder, tiny_prior_path, *extra)
    assert code == 0, err
    assert err.count("zedo: warning:") == 1 and "'Pacifier'" in err  # the unknown label, once
    doc = json.loads(out)
    assert doc["input"]["format"] == "labelme" and len(doc["frames"]) == 4
    joints, others = doc["skeleton"]["joints"], doc["other_keypoints"]["joints"]
    by_name = {name: label for label, name in NYCU_LABELS.items()}
    assert set(joints) | set(others) == set(by_name)  # every labelled point is in the result, by name
    for frame, n in zip(doc["frames"], (1, 2, 3, 4), strict=True):
        person = frame["persons"][0]
        pixels = pose_pixels(float(n))
        for j, name in enumerate(joints):
            assert person["keypoints_2d"][j] == list(pixels[name]), (n, name)
        for e, name in enumerate(others):
            assert person["other_keypoints_2d"][e] == list(pixels[name]), (n, name)


def test_a_label_studio_export_lifts(tiny_prior_path: Path, tmp_path: Path) -> None:
    tasks = [ls_task(k, nycu_label_studio_results(float(k)), image=f"/data/upload/1/f{k}.jpg") for k in (1, 2)]
    code, out, err = _lift(write_json(tmp_path / "project-1-at-2025.json", tasks), tiny_prior_path, "-q")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["input"]["format"] == "label-studio" and doc["summary"]["instances_lifted"] >= 1
    knee = doc["skeleton"]["joints"].index("left_knee")
    got = doc["frames"][1]["persons"][0]["keypoints_2d"][knee]
    assert got == pytest.approx(list(pose_pixels(2.0)["left_knee"]), abs=1e-3)


@pytest.mark.parametrize(
    ("make", "said"),
    [
        (lambda t: write_json(t / "bad.json", labelme_doc([{**labelme_shape("Knee_L", 1.0, 2.0), "shape_type": "line",
                                                              "points": [[1, 2], [3, 4]]}])),
         "bad.json: shapes: no point shapes"),
        (lambda t: write_json(t / "bad.json", labelme_doc([labelme_shape("Pacifier", 1.0, 2.0),
                                                           labelme_shape("Blanket", 3.0, 4.0)])),
         "bad.json: no label names a body joint ('Pacifier', 'Blanket')"),
        (lambda t: write_json(t / "bad.json", [ls_task(1, [ls_result("Knee_L", 1400.0, 20.0)])]),
         "bad.json: [0].annotations[0].result[0].value.x: expected a percentage of the image's width in [0, 100]"),
    ],
)  # fmt: skip
def test_bad_annotation_files_are_one_line_exit_3(make, said: str, tiny_prior_path: Path, tmp_path: Path) -> None:
    code, out, err = _lift(make(tmp_path), tiny_prior_path)
    assert code == 3 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("zedo: error: ") and said in lines[0], err
    assert "Traceback" not in err
