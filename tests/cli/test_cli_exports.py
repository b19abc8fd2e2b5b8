"""The export targets of docs/exports.md from the command line: a 61-frame clip at 30 fps with one
empty frame, lifted to TRC and C3D, equals its JSON in the stated axes within 0.1 mm, NaN exactly
where the JSON has no pose; stdout and frames without numbers are refused with one line."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from export_fixtures import EMPTY, FPS, FRAMES, UNLIFTED, json_markers, lift_clip, write_clip
from helpers import write_coco
from typer.testing import CliRunner

from zedo_cli.cli import app
from zedo_cli.formats.result_schema import ResultDocument, result_json_schema

runner = CliRunner()


@pytest.fixture(scope="module")
def clip(tiny_prior_path: Path, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    return lift_clip(tiny_prior_path, tmp_path_factory.mktemp("clip"))


def test_the_json_fits_the_published_schema(clip: dict[str, Path]) -> None:
    doc = json.loads(clip["json"].read_text(encoding="utf-8"))
    ResultDocument.model_validate(doc, context={"joints": 12})
    jsonschema = pytest.importorskip("jsonschema")
    jsonschema.validate(doc, result_json_schema(), cls=jsonschema.Draft202012Validator)


def test_trc_equals_the_json(clip: dict[str, Path]) -> None:
    lines = clip["trc"].read_text(encoding="utf-8").splitlines()
    assert lines[2].split("\t") == [str(FPS), str(FPS), str(FRAMES), "12", "m", str(FPS), "1", str(FRAMES)]
    rows = np.array([[float(v) for v in line.split("\t")] for line in lines[5:]])
    assert rows.shape == (FRAMES, 2 + 36)
    np.testing.assert_allclose(rows[:, 1], np.arange(FRAMES) / FPS, atol=1e-6)
    expected = json_markers(clip["json"])
    xyz = rows[:, 2:].reshape(FRAMES, 12, 3)
    np.testing.assert_array_equal(np.isnan(xyz), np.isnan(expected))
    assert np.isnan(xyz[[EMPTY, UNLIFTED]]).all() and np.isnan(xyz).any(axis=(1, 2)).sum() == 2
    np.testing.assert_allclose(xyz, expected, atol=1e-4, equal_nan=True)  # 0.1 mm


def test_c3d_equals_the_json(clip: dict[str, Path]) -> None:
    ezc3d = pytest.importorskip("ezc3d")
    c3d = ezc3d.c3d(str(clip["c3d"]))
    point = c3d["parameters"]["POINT"]
    assert point["RATE"]["value"][0] == FPS and point["UNITS"]["value"] == ["mm"]
    xyz = c3d["data"]["points"][:3].transpose(2, 1, 0) / 1000.0  # (F, M, 3) m
    expected = json_markers(clip["json"])
    np.testing.assert_array_equal(np.isnan(xyz), np.isnan(expected))
    np.testing.assert_allclose(xyz, expected, atol=1e-4, equal_nan=True)


def test_refused_with_one_line(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_clip(tmp_path / "clip.jsonl")
    coco = write_coco(tmp_path / "kp.json")  # images, no frame numbers
    base = ["lift", "--prior", str(tiny_prior_path), "--steps", "5", "-q"]
    cases = [
        ([str(src), "-o", "-", "--output-format", "trc"], "cannot go to stdout"),
        ([str(src), "-o", "-", "--output-format", "c3d"], "cannot go to stdout"),
        ([str(coco), "-o", str(tmp_path / "kp.trc")], "no frame numbers"),
        ([str(src), "-o", str(tmp_path / "a.trc"), "--marker-axes", "sideways"], "--marker-axes"),
    ]
    for args, needle in cases:
        result = runner.invoke(app, [*base, *args])
        assert result.exit_code == 2, result.output
        assert needle in result.output and len(result.output.strip().splitlines()) == 1, result.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["clip.jsonl", "kp.json"]
