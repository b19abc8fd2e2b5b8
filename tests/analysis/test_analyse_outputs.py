"""The analysis of whole results: rows, calls with and without uncertainty, movement features,
the CSV / JSON outputs and the HTML report."""

from __future__ import annotations

import csv
import io
import json
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from analysis_results import kicking_poses, result_document, write_document

from zedo_cli.analysis.analyse import COLUMNS, AnalysisSettings, analyse
from zedo_cli.analysis.outputs import analysis_document, csv_text, write_csv, write_json
from zedo_cli.errors import ConfigError, InputFormatError
from zedo_cli.formats.result_reader import read_result


@pytest.fixture()
def kick(tmp_path: Path) -> Path:
    return write_document(tmp_path / "kick.zedo.json", result_document(kicking_poses(60), fps=30.0))


@pytest.fixture()
def kick_calibrated(tmp_path: Path) -> tuple[Path, list]:
    """A clip whose params match a test calibration of +-5 degrees around the measured value."""
    from test_calibration import PARAMS, calibration

    doc = result_document(kicking_poses(60), fps=30.0)
    doc["params"].update({**PARAMS, "temporal": {"mode": "smooth"}})
    return write_document(tmp_path / "kickc.zedo.json", doc), [calibration("smooth")]


def rows_of(text: str) -> list[dict[str, str]]:
    return list(csv.DictReader(io.StringIO(text)))


def test_rows_without_a_calibration_say_so(kick: Path) -> None:
    a = analyse(read_result(kick))
    rows = rows_of(csv_text(a))
    assert list(rows[0]) == list(COLUMNS)
    assert list(COLUMNS[:10]) == ["frame_index", "image_id", "file_name", "person", "measure", "value", "unit",
                                  "low_90", "high_90", "call"]  # fmt: skip
    head_rows = [r for r in rows if r["measure"].startswith("head_")]
    frame_rows = [r for r in rows if r["frame_index"] and not r["measure"].startswith("head_")]
    assert len(frame_rows) == 60 * (4 + 4 + 12)
    # a result written without the input's face points: empty head rows with the reason, one note
    assert len([r for r in head_rows if r["frame_index"]]) == 60 * 2
    assert all(r["value"] == "" and "lift it again" in r["interval"] for r in head_rows)
    assert sum("no head measures" in n for n in a.notes) == 1
    assert all(r["low_90"] == "" and r["high_90"] == "" for r in rows)
    assert {r["interval"] for r in frame_rows} == {"none: no measure calibration for this prior"}
    assert {r["call"] for r in frame_rows if r["measure"].startswith("symmetry_") and r["unit"] == "deg"} == {
        "uncertain"}  # fmt: skip
    shank = [float(r["value"]) for r in frame_rows if r["measure"] == "symmetry_shank_deg"]
    knee = [float(r["value"]) for r in frame_rows if r["measure"] == "left_knee_flexion_deg"]
    np.testing.assert_allclose(shank, knee, atol=1e-3)  # a straight right leg: the shank angle is the knee bend
    assert max(knee) == pytest.approx(60.0, abs=0.01)
    assert any("no calibrated intervals" in n for n in a.notes)
    assert [r["value"] for r in frame_rows] == [r["raw_value"] for r in frame_rows]  # nothing calibrated


def test_movement_features_of_a_kicking_leg(kick_calibrated: tuple[Path, list]) -> None:
    a = analyse(read_result(kick_calibrated[0]), calibrations=kick_calibrated[1])
    clip = {r.measure: r.value for r in a.rows if r.frame_index is None}
    assert clip["left_knee_flexion_range_deg"] == pytest.approx(60.0, abs=0.01)
    assert clip["right_knee_flexion_range_deg"] == pytest.approx(0.0, abs=1e-6)
    # theta_t = 30 - 30 cos(2 pi t / 30) at 30 fps: the velocities are 30 * its frame differences
    theta = 30.0 - 30.0 * np.cos(2 * np.pi * np.arange(60) / 30.0)
    speed = 30.0 * np.abs(np.diff(theta))
    assert clip["left_knee_flexion_median_abs_velocity_deg_s"] == pytest.approx(np.median(speed), rel=1e-3)
    q25, q75 = np.percentile(speed, [25, 75])
    assert clip["left_knee_flexion_abs_velocity_iqr_deg_s"] == pytest.approx(q75 - q25, rel=1e-3)
    assert clip["right_knee_flexion_median_abs_velocity_deg_s"] == pytest.approx(0.0, abs=1e-6)
    assert np.isnan(clip["knee_flexion_left_right_correlation"])  # the right knee does not move
    assert 0.0 < clip["symmetry_shank_fraction_symmetric"] < 1.0
    assert clip["symmetry_thigh_fraction_symmetric"] == 1.0  # 0 +- 5 degrees: symmetric in every frame


def test_without_fps_there_are_no_movement_features(tmp_path: Path) -> None:
    path = write_document(tmp_path / "x.zedo.json", result_document(kicking_poses(5)))
    a = analyse(read_result(path))
    assert not any(r.frame_index is None for r in a.rows) and any("no fps" in n for n in a.notes)
    a = analyse(read_result(path), AnalysisSettings(fps=10.0))
    assert a.fps_source == "option" and any(r.frame_index is None for r in a.rows)


def test_intervals_and_uncertain_calls_from_a_calibration(kick_calibrated: tuple[Path, list]) -> None:
    a = analyse(read_result(kick_calibrated[0]), calibrations=kick_calibrated[1])
    shank = [r for r in a.rows if r.measure == "symmetry_shank_deg"]
    assert all(r.interval == "calibrated" and r.low_90 <= r.high_90 for r in shank)
    assert all(r.low_90 >= 0.0 for r in shank)
    calls = {r.call for r in shank}
    assert calls == {"symmetric", "asymmetric", "uncertain"}
    for r in shank:  # uncertain exactly when the interval straddles the threshold
        assert (r.call == "uncertain") == (r.low_90 <= 28.0 < r.high_90)
    doc = analysis_document(a)
    assert doc["uncertainty"]["available"] and doc["uncertainty"]["note"] == "calibrated"
    assert doc["summary"]["symmetry_shank_deg"]["uncertain"] == sum(r.call == "uncertain" for r in shank)


def test_json_holds_the_rows_settings_and_the_note(kick: Path, tmp_path: Path) -> None:
    a = analyse(read_result(kick), AnalysisSettings(threshold_deg=30.0))
    out = tmp_path / "a.json"
    write_json(a, out)
    doc = json.loads(out.read_text())
    assert doc["schema"] == "zedo.analysis/1" and doc["settings"]["symmetry_threshold_deg"] == 30.0
    assert doc["settings"]["fps"] == 30.0 and doc["settings"]["fps_source"] == "result"
    assert doc["uncertainty"]["available"] is False and "no measure calibration" in doc["uncertainty"]["note"]
    assert len(doc["rows"]) == len(a.rows) and doc["rows"][0]["measure"] == "symmetry_upper_arm_deg"
    assert doc["rows"][0]["low_90"] is None and doc["columns"] == list(COLUMNS)
    with pytest.raises(ConfigError, match="already exists"):
        write_csv(a, out)


def test_bad_settings_and_unlifted_results(tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match="threshold"):
        AnalysisSettings(threshold_deg=-1.0)
    with pytest.raises(ConfigError, match="fps"):
        AnalysisSettings(fps=0.0)
    with pytest.raises(ConfigError, match="--level"):
        AnalysisSettings(level=0.85)
    with pytest.raises(ConfigError, match="--max-angular-velocity"):
        AnalysisSettings(max_velocity_deg_s=0.0)
    doc = result_document(kicking_poses(2))
    for frame in doc["frames"]:
        frame["persons"][0]["keypoints_3d"] = None
    with pytest.raises(InputFormatError, match="u.zedo.json: no lifted person"):
        analyse(read_result(write_document(tmp_path / "u.zedo.json", doc)))


def test_the_report_is_self_contained(kick_calibrated: tuple[Path, list], tmp_path: Path) -> None:
    from zedo_cli.analysis.report import write_report

    a = analyse(read_result(kick_calibrated[0]), calibrations=kick_calibrated[1])
    out = write_report(a, tmp_path / "r.html")
    page = out.read_text()
    assert page.index("Decisions") < page.index("Skeleton views")  # the calls lead
    assert page.startswith("<!DOCTYPE html>") and page.count("<svg") == 3 + 1  # 3 skeleton views, 1 time series
    for needle in ("Decisions", "Symmetry per frame", "Joint angles per frame", "Time series", "Movement features",
                   "<b>Uncertain</b>: that interval includes 28°", "80% interval"):  # fmt: skip
        assert needle in page
    # nothing to fetch: no scripts, no external stylesheet, image or font
    assert "<script" not in page and "<link" not in page and "<img" not in page
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:)?//""", page)
    assert "@import" not in page and not re.search(r"url\((?!#)", page)  # only the SVGs' own clip paths


def test_no_calibration_is_stated_in_the_report(kick: Path, tmp_path: Path) -> None:
    from zedo_cli.analysis.report import report_html

    page = report_html(analyse(read_result(kick)))
    assert "No decisive calls." in page and "no measure calibration for this prior" in page


def test_matplotlib_is_loaded_only_for_a_report(kick: Path) -> None:
    code = (
        "import sys\n"
        "from zedo_cli.analysis import analyse, write_csv\n"
        "from zedo_cli.formats.result_reader import read_result\n"
        f"write_csv(analyse(read_result({str(kick)!r})), '-')\n"
        "assert 'matplotlib' not in sys.modules\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.startswith("frame_index,")
