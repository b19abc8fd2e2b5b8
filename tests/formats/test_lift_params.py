"""`LiftParams`: the typed view of a result's recorded `params`, and `ResultPoses.lift_params`."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest
from writer_fixtures import INPUT_INFO, PARAMS, make_case

from zedo_cli.errors import InputFormatError
from zedo_cli.formats.readers.result import LiftParams, read_result
from zedo_cli.formats.writers.outputs import write_result

FULL = {
    "fps": 25,
    "temporal": {"mode": "smooth", "sigma_frames": 2.0},
    "camera_sources": ["pseudo"],
    "prior": {"sha256": "ab" * 32},
    "config": {"steps": 200},
    "min_confidence": 0.3,
}


def test_the_fields_read_typed() -> None:
    got = LiftParams.from_dict(FULL)
    assert got == LiftParams(25.0, "smooth", ("pseudo",), "ab" * 32, {"steps": 200}, 0.3)
    assert isinstance(got.fps, float)


@pytest.mark.parametrize("params", [{}, None, "params", {"temporal": "smooth", "prior": [], "camera_sources": "cli"}])
def test_an_older_or_odd_file_reads_as_none(params: object) -> None:
    assert LiftParams.from_dict(params) == LiftParams()


def test_a_bad_fps_is_refused_when_reading_a_file_else_none() -> None:
    with pytest.raises(InputFormatError, match=r"^kp\.csv: params\.fps: expected a positive number or null, got -1$"):
        LiftParams.from_dict({"fps": -1}, "kp.csv")
    assert LiftParams.from_dict({"fps": "x"}).fps is None


@pytest.mark.parametrize("fmt", ["json", "jsonl", "csv", "npz"])
def test_every_format_gives_the_typed_params_beside_the_raw_dict(tmp_path: Path, fmt: str) -> None:
    kp, res, mats, sources = make_case()
    path = tmp_path / f"kp.zedo.{fmt}"
    write_result(path, kp, res, mats, sources, {**PARAMS, **FULL}, INPUT_INFO)
    got = read_result(path)
    assert got.params["temporal"] == FULL["temporal"]  # the raw dict, as recorded
    assert got.lift_params == LiftParams.from_dict(got.params)
    assert got.lift_params.fps == got.fps == 25.0 and got.lift_params.temporal_mode == "smooth"
    changed = dataclasses.replace(got, params={**got.params, "min_confidence": 0.5})
    assert changed.lift_params.min_confidence == 0.5  # built from the copy's own params
