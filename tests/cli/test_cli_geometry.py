"""`zedo lift` on impossible cameras and geometry: input files that can never
work are input errors (exit 3), and an instance that cannot be lifted is flagged in an output
that keeps the others. (Camera options that can never work: test_cli_options.py, exit 2.)"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from test_cli import lift_args, runner, write_coco

from zedo_cli.cli import app


def _edit_coco(path: Path, edit: object) -> Path:
    doc = json.loads(path.read_text())
    edit(doc)  # type: ignore[operator]
    path.write_text(json.dumps(doc))
    return path


def test_one_degenerate_instance_is_flagged_and_the_others_lifted(tiny_prior_path: Path, tmp_path: Path) -> None:
    def centre_all(doc: dict) -> None:  # every joint of the first person at the image centre (the principal point)
        kp = doc["annotations"][0]["keypoints"]
        for j in range(17):
            if kp[3 * j + 2] > 0:
                kp[3 * j : 3 * j + 2] = [320.0, 240.0]

    src = _edit_coco(write_coco(tmp_path / "kp.json", n=3), centre_all)
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src)))
    assert result.exit_code == 0, result.output
    doc = json.loads((tmp_path / "kp.zedo.json").read_text())
    first, *rest = [p for f in doc["frames"] for p in f["persons"]]
    assert first["flags"] == ["not_lifted_degenerate_geometry"] and first["keypoints_3d"] is None
    assert all(p["keypoints_3d"] is not None and p["flags"] == [] for p in rest)
    assert doc["summary"]["instances_lifted"] == 2 and doc["summary"]["not_lifted"] == {"degenerate_geometry": 1}


def test_an_input_where_nothing_can_be_lifted_is_an_input_error(tiny_prior_path: Path, tmp_path: Path) -> None:
    def huge(doc: dict) -> None:
        for ann in doc["annotations"]:
            ann["keypoints"] = [1e200 if (i % 3 != 2 and v != 0) else v for i, v in enumerate(ann["keypoints"])]

    src = _edit_coco(write_coco(tmp_path / "kp.json", n=2), huge)
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src)))
    assert result.exit_code == 3, result.output
    assert "no instance can be lifted (2 ray_out_of_range" in result.output
    assert len(result.output.strip().splitlines()) == 1 and not (tmp_path / "kp.zedo.json").exists()


@pytest.mark.parametrize(
    ("edit", "needle"),
    [
        (lambda d: d["images"][0].update(width=1e300, height=1e300), "out of range"),
        (lambda d: [im.pop("width") for im in d["images"]], "image size"),  # a COCO image without width
    ],
)
def test_image_sizes_that_cannot_work_are_input_errors(
    tiny_prior_path: Path, tmp_path: Path, edit: object, needle: str
) -> None:
    src = _edit_coco(write_coco(tmp_path / "kp.json", n=1), edit)
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src)))
    assert result.exit_code == 3, result.output
    assert needle in result.output and str(src) in result.output


@pytest.mark.parametrize(
    "content",
    ["{not json", json.dumps({"fx": 1e30, "fy": 1e30, "cx": 1, "cy": 1}), json.dumps({"other": 1}),
     json.dumps({"images": {"10": {"fx": 1000, "cx": 10, "cy": 10}}})],
)  # fmt: skip
def test_a_bad_intrinsics_file_is_an_input_error(tiny_prior_path: Path, tmp_path: Path, content: str) -> None:
    src = write_coco(tmp_path / "kp.json", n=1)
    k_file = tmp_path / "K.json"
    k_file.write_text(content)
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "--intrinsics", str(k_file)))
    assert result.exit_code == 3, result.output
    assert str(k_file) in result.output and len(result.output.strip().splitlines()) == 1


@pytest.mark.parametrize("where", ["tensor", "sde_config"])
def test_a_prior_holding_nan_is_refused_up_front(tiny_prior_path: Path, tmp_path: Path, where: str) -> None:
    """Today's bug: exit 0, "lifted 3/3", every coordinate null. Now: exit 3 before any lifting."""
    from safetensors import safe_open
    from safetensors.torch import load_file, save_file

    with safe_open(str(tiny_prior_path), framework="pt") as fh:
        meta = dict(fh.metadata())
    tensors = load_file(str(tiny_prior_path))
    if where == "tensor":
        tensors["model.head.bias"] = tensors["model.head.bias"].clone().fill_(float("nan"))
    else:
        meta["sde_config"] = json.dumps({"type": "subvp", "beta_min": float("nan"), "beta_max": 20.0,
                                         "num_scales": 1000})  # fmt: skip
    bad = tmp_path / "nan.safetensors"
    save_file(tensors, str(bad), metadata=meta)
    src = write_coco(tmp_path / "kp.json")
    result = runner.invoke(app, ["lift", "--prior", str(bad), "--steps", "30", "-q", str(src)])
    assert result.exit_code == 3, result.output
    assert str(bad) in result.output and len(result.output.strip().splitlines()) == 1
    assert not (tmp_path / "kp.zedo.json").exists()
