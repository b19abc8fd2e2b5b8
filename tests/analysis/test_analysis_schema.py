"""The analysis file's published schema (`zedo.analysis/2`): what zedo analyze writes validates against it, the
schema file in docs/ is the generated one, and `zedo schema analysis` prints it."""

from __future__ import annotations

import json
import typing
from pathlib import Path

import jsonschema
import pytest
from analysis_results import kicking_poses, result_document, write_document
from typer.testing import CliRunner

from zedo_cli.analysis.analyse import analyse
from zedo_cli.analysis.outputs import write_json
from zedo_cli.analysis.schema import SCHEMA, AnalysisDocument, AnalysisRow, IntervalMethod, analysis_json_schema
from zedo_cli.analysis.table import COLUMNS, INTERVAL_METHODS
from zedo_cli.cli import app
from zedo_cli.formats.readers.result import read_result

SCHEMA_FILE = Path(__file__).resolve().parents[2] / "docs" / "schema" / "zedo.analysis-2.schema.json"


def test_the_rows_model_has_the_tables_columns_and_codes() -> None:
    assert tuple(AnalysisRow.model_fields) == COLUMNS
    assert set(typing.get_args(IntervalMethod)) == {"", *INTERVAL_METHODS}


@pytest.mark.parametrize("fps", [30.0, None])
def test_what_zedo_analyze_writes_validates(tmp_path: Path, fps: float | None) -> None:
    a = analyse(read_result(write_document(tmp_path / "k.zedo.json", result_document(kicking_poses(40), fps=fps))))
    write_json(a, tmp_path / "k.analysis.json")
    doc = json.loads((tmp_path / "k.analysis.json").read_text())
    jsonschema.validate(doc, analysis_json_schema(), cls=jsonschema.Draft202012Validator)
    model = AnalysisDocument.model_validate(doc)
    assert model.schema_ == SCHEMA and model.columns == list(COLUMNS)
    assert {r.interval for r in model.rows} <= {"", *INTERVAL_METHODS}
    broken = {**doc, "rows": [{**doc["rows"][0], "interval": "none: a reason"}]}  # the code and the note apart
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(broken, analysis_json_schema(), cls=jsonschema.Draft202012Validator)


def test_the_published_schema_file_is_the_generated_one() -> None:
    assert json.loads(SCHEMA_FILE.read_text(encoding="utf-8")) == analysis_json_schema(), (
        "regenerate with: zedo schema analysis -o docs/schema/zedo.analysis-2.schema.json --overwrite"
    )
    result = CliRunner().invoke(app, ["schema", "analysis"])
    assert result.exit_code == 0 and json.loads(result.stdout) == analysis_json_schema()
