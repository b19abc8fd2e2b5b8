"""The published result schema: every JSON and JSON Lines output of the writers validates against
the generated JSON Schema (jsonschema) and the pydantic models (with the per-joint lengths), the
schema file in docs/ is the generated one, and `zedo schema result` prints it."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from typer.testing import CliRunner
from writer_fixtures import INPUT_INFO, PARAMS, make_case

from zedo_cli.cli import app
from zedo_cli.formats.result_schema import (
    FrameLine,
    HeaderLine,
    ResultDocument,
    SummaryLine,
    result_json_schema,
)
from zedo_cli.formats.writers.outputs import write_result

jsonschema = pytest.importorskip("jsonschema")
SCHEMA_FILE = Path(__file__).resolve().parents[2] / "docs" / "schema" / "zedo.pose3d-1.schema.json"
VALIDATOR = jsonschema.Draft202012Validator(result_json_schema())


def check_document(doc: dict[str, Any]) -> None:
    """`doc` fits the JSON Schema and the models (one entry per joint in every per-joint list)."""
    errors = [f"{'/'.join(map(str, e.absolute_path))}: {e.message}" for e in VALIDATOR.iter_errors(doc)]
    assert errors == []
    ResultDocument.model_validate(doc, context={"joints": len(doc["skeleton"]["joints"])})


def check_jsonl(text: str) -> dict[str, Any]:
    """Every line fits its model; joined, they are a document that fits the schema (returned)."""
    lines = [json.loads(line) for line in text.splitlines()]
    joints = len(lines[0]["skeleton"]["joints"])
    HeaderLine.model_validate(lines[0])
    for line in lines[1:-1]:
        FrameLine.model_validate(line, context={"joints": joints})
    SummaryLine.model_validate(lines[-1])
    strip = [{k: v for k, v in line.items() if k != "type"} for line in lines]
    doc = {**strip[0], "frames": strip[1:-1], "summary": strip[-1]}
    check_document(doc)
    return doc


def variants() -> list[tuple[str, Any, Any, dict[str, Any]]]:
    """(label, kp, res, write_result options) covering every optional part of the document."""
    kp, res, _, _ = make_case()
    rng = np.random.default_rng(0)
    radii = np.where(res.lifted[:, None], 0.02, np.nan) * np.ones((len(kp), 12))
    hyps = rng.normal(0.0, 0.1, (len(kp), 3, 12, 3))
    return [
        ("default", kp, res, {}),
        ("mm-root", kp, res, {"units": "mm", "frame": "root"}),
        (
            "uncertainty-hypotheses",
            kp,
            replace(res, uncertainty_m=radii, hypotheses=hyps, hypothesis_spread_m=np.where(res.lifted, 0.09, np.nan)),
            {},
        ),  # fmt: skip
        ("string-ids", replace(kp, image_ids=["a", "a", "b", "c"]), res, {"units": "mm"}),
    ]


@pytest.mark.parametrize("index", range(4))
def test_every_json_and_jsonl_output_fits_the_schema(tmp_path: Path, index: int) -> None:
    label, kp, res, options = variants()[index]
    _, _, mats, sources = make_case()
    write_result(tmp_path / "r.json", kp, res, mats, sources, {**PARAMS, "fps": 25.0}, INPUT_INFO, **options)
    write_result(tmp_path / "r.jsonl", kp, res, mats, sources, PARAMS, INPUT_INFO, **options)
    doc = json.loads((tmp_path / "r.json").read_text())
    check_document(doc)
    joined = check_jsonl((tmp_path / "r.jsonl").read_text())
    assert joined["frames"] == doc["frames"], label


def test_a_writer_change_that_breaks_the_schema_is_caught(tmp_path: Path) -> None:
    kp, res, mats, sources = make_case()
    write_result(tmp_path / "r.json", kp, res, mats, sources, PARAMS, INPUT_INFO)
    doc = json.loads((tmp_path / "r.json").read_text())
    broken = [
        ("frames", 0, "persons", 0, "keypoints_3d", 0, 0),  # a number as a string
        ("frames", 0, "camera", "K"),  # a matrix as a flat list
        ("frames", 0, "persons", 0, "confidence"),  # a field the schema does not know
    ]
    for path in broken:
        bad = json.loads(json.dumps(doc))
        target = bad
        for key in path[:-1]:
            target = target[key]
        value = target.get(path[-1]) if isinstance(target, dict) else target[path[-1]]
        target[path[-1]] = str(value) if path[-1] == 0 else (sum(value, []) if path[-1] == "K" else 0.5)
        assert list(VALIDATOR.iter_errors(bad)), path


def test_docs_carry_the_generated_schema() -> None:
    assert json.loads(SCHEMA_FILE.read_text(encoding="utf-8")) == result_json_schema(), (
        "regenerate with: zedo schema result -o docs/schema/zedo.pose3d-1.schema.json --overwrite"
    )


def test_schema_command(tmp_path: Path) -> None:
    runner = CliRunner()
    result = runner.invoke(app, ["schema", "result"])
    assert result.exit_code == 0 and json.loads(result.stdout) == result_json_schema()
    assert runner.invoke(app, ["schema", "result", "-o", str(tmp_path / "s.json")]).exit_code == 0
    again = runner.invoke(app, ["schema", "result", "-o", str(tmp_path / "s.json")])
    assert again.exit_code == 2 and "already exists" in again.output
    bad = runner.invoke(app, ["schema", "norms"])
    assert bad.exit_code == 2 and "unknown schema 'norms'; choose one of: result, analysis" in bad.output


def test_a_clip_mode_results_skeletons_fit_the_schema(tmp_path: Path) -> None:
    from zedo_cli.lifting.clip import TrackSkeleton

    kp, res, mats, sources = make_case()
    bones = {"left_upper_arm": 0.11, "right_upper_arm": 0.112, "left_thigh": 0.14, "right_thigh": 0.138}
    found = TrackSkeleton(track=0, frames=300, bones_m=bones, torso_m={"hip_width": 0.1, "trunk_length": 0.25})
    lost = TrackSkeleton(track="b", frames=12, fallback="under 1 s of frames")
    temporal = {"mode": "clip", "sigma_frames": 2.0, "skeletons": [found.to_dict(), lost.to_dict()]}
    write_result(tmp_path / "r.json", kp, res, mats, sources, {**PARAMS, "temporal": temporal}, INPUT_INFO)
    doc = json.loads((tmp_path / "r.json").read_text())
    check_document(doc)
    bad = json.loads(json.dumps(doc))
    bad["params"]["temporal"]["skeletons"][0]["bones"]["left_thigh"]["share"] = "0.3"
    assert list(VALIDATOR.iter_errors(bad))
