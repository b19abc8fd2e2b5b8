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
from zedo_cli.formats.readers.result import read_result


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
    assert list(COLUMNS[:13]) == ["frame_index", "image_id", "file_name", "person", "measure", "value", "unit",
                                  "low", "high", "level", "call", "interval", "interval_note"]  # fmt: skip
    assert all(r["level"] == "" for r in rows)  # no interval, no level
    head_rows = [r for r in rows if r["measure"].startswith("head_")]
    frame_rows = [r for r in rows if r["frame_index"] and not r["measure"].startswith("head_")]
    assert len(frame_rows) == 60 * (4 + 4 + 4 + 12)  # angle, band and probability per pair; 12 joint angles
    # a result written without the input's face points: empty head rows with the reason, one note
    assert len([r for r in head_rows if r["frame_index"]]) == 60 * 2
    assert all(r["value"] == "" and "lift it again" in r["interval_note"] for r in head_rows)
    assert sum("no head measures" in n for n in a.notes) == 1
    assert all(r["low"] == "" and r["high"] == "" for r in rows)
    assert {(r["interval"], r["interval_note"]) for r in frame_rows} == {
        ("none", "no measure calibration for this prior")
    }
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
    assert all(r.how == "calibrated" and r.low <= r.high for r in shank)
    assert all(r.low >= 0.0 for r in shank)
    calls = {r.call for r in shank}
    assert calls == {"symmetric", "asymmetric", "uncertain"}
    for r in shank:  # uncertain exactly when the interval straddles the threshold
        assert (r.call == "uncertain") == (r.low <= 28.0 < r.high)
    doc = analysis_document(a)
    assert doc["uncertainty"]["available"] and doc["uncertainty"]["note"] == "calibrated"
    assert doc["summary"]["symmetry_shank_deg"]["uncertain"] == sum(r.call == "uncertain" for r in shank)


def test_json_holds_the_rows_settings_and_the_note(kick: Path, tmp_path: Path) -> None:
    a = analyse(read_result(kick), AnalysisSettings(threshold_deg=30.0))
    out = tmp_path / "a.json"
    write_json(a, out)
    doc = json.loads(out.read_text())
    assert doc["schema"] == "zedo.analysis/2" and doc["settings"]["symmetry_threshold_deg"] == 30.0
    assert doc["settings"]["fps"] == 30.0 and doc["settings"]["fps_source"] == "result"
    assert doc["uncertainty"]["available"] is False and "no measure calibration" in doc["uncertainty"]["note"]
    assert len(doc["rows"]) == len(a.rows) and doc["rows"][0]["measure"] == "symmetry_upper_arm_deg"
    assert doc["rows"][0]["low"] is None and doc["columns"] == list(COLUMNS)
    with pytest.raises(ConfigError, match="already exists"):
        write_csv(a, out)


def test_the_files_are_written_a_row_at_a_time_as_the_whole_document_would_be(kick: Path, tmp_path: Path) -> None:
    """write_json streams the rows (a 10-minute clip has about half a million), each on a line of its own,
    and writes the JSON of the whole document; write_csv what the csv module writes of every row."""
    import csv

    a = analyse(read_result(kick))
    write_json(a, tmp_path / "a.json")
    written = (tmp_path / "a.json").read_text()
    whole = analysis_document(a)
    doc = json.loads(written)
    assert {**doc, "created": ""} == {**whole, "created": ""} and len(doc["rows"]) == len(a.rows)
    lines = written.splitlines()
    first = lines.index(' "rows": [') + 1
    assert [json.loads(line.rstrip(",")) for line in lines[first : first + len(a.rows)]] == whole["rows"]
    write_csv(a, tmp_path / "a.csv")
    with (tmp_path / "a.csv").open(newline="") as fh:
        table = list(csv.reader(fh))
    assert table[0] == list(COLUMNS) and len(table) == len(a.rows) + 1
    assert table[1][COLUMNS.index("measure")] == a.rows[0].measure
    with pytest.raises(ConfigError, match="already exists"):
        write_json(a, tmp_path / "a.json")


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
    from zedo_cli.analysis.report.report import write_report

    a = analyse(read_result(kick_calibrated[0]), calibrations=kick_calibrated[1])
    out = write_report(a, tmp_path / "r.html")
    page = out.read_text()
    assert page.index("Decisions") < page.index("Skeleton views")  # the calls lead
    assert page.startswith("<!DOCTYPE html>") and page.count("<svg") == 3 + 2  # 3 skeleton views, 2 time series
    for needle in ("Decisions", "Symmetry per frame", "Joint angles per frame", "over time", "Movement features",
                   "zedo calls a pair <b>symmetric</b> only when the whole 80 % interval"):  # fmt: skip
        assert needle in page
    # nothing to fetch: no scripts, no external stylesheet, image or font
    assert "<script" not in page and "<link" not in page and "<img" not in page
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:)?//""", page)
    assert "@import" not in page and not re.search(r"url\((?!#)", page)  # only the SVGs' own clip paths


def test_the_report_prints_beside_each_call_the_interval_that_decides_it(
    kick_calibrated: tuple[Path, list],
) -> None:
    from dataclasses import replace

    from zedo_cli.analysis.report.report import report_html

    cal = kick_calibrated[1][0]  # widths that grow with the level: 3 degrees at 70 %, 9 at 90 %
    widths = {level: (3.0 if level <= 0.7 else 9.0,) for level in cal.measures["symmetry_thigh_deg"].q_low}
    models = {n: replace(m, q_low=widths, q_high=widths) for n, m in cal.measures.items()}
    a = analyse(read_result(kick_calibrated[0]), AnalysisSettings(level=0.9, call_level=0.7),
                calibrations=[replace(cal, measures=models)])  # fmt: skip
    page = report_html(a)
    table = page[page.index("<h2>Symmetry per frame</h2>") : page.index("<h2>Joint angles per frame</h2>")]
    assert "70 % interval that decides the call" in table and table.count("deg [70 %] call") == 4
    rows = [r for r in a.rows if r.measure.startswith("symmetry_") and r.unit == "deg" and r.frame_index is not None]
    assert rows and all(np.isfinite(r.call_low) and (r.call_low, r.call_high) != (r.low, r.high) for r in rows)
    assert {(r.level, r.interval, r.interval_note) for r in rows} == {(0.9, "calibrated", "")}  # low, high at --level
    assert {r["level"] for r in rows_of(csv_text(a)) if r["low"]} == {"0.9"}
    for r in rows[:8]:  # each call's cell holds the 70 % interval, never the 90 % one
        cell = f"[{r.call_low:.1f}, {r.call_high:.1f}]</small> <small>{r.call}</small>"
        assert cell in table, cell
        assert f"[{r.low:.1f}, {r.high:.1f}]</small> <small>{r.call}" not in table


def test_the_report_opens_with_the_research_notice_and_shows_bands_as_the_papers(
    kick_calibrated: tuple[Path, list],
) -> None:
    from zedo_cli.analysis.report.report import report_html
    from zedo_cli.footage.draw import LEFT, RIGHT
    from zedo_cli.formats.colours import LEFT_HEX, LEFT_RGB, RIGHT_HEX, RIGHT_RGB, bgr

    page = report_html(analyse(read_result(kick_calibrated[0]), calibrations=kick_calibrated[1]))
    notice = page.index("For research; not a diagnosis.")
    assert page.index("</h1>") < notice < page.index("<h2>Decisions</h2>")
    assert "research / non-commercial use only" in page
    symmetry = page[page.index("<h2>Symmetry</h2>") : page.index("<h2>Skeleton views</h2>")]
    assert "poses per band of Huang et al. (not the call)" in symmetry and "symmetric</th>" not in symmetry
    assert (bgr(LEFT_RGB), bgr(RIGHT_RGB)) == (LEFT, RIGHT)  # zedo render's colours are the report's
    assert f"color:{LEFT_HEX}'>blue</b> = left" in page and f"color:{RIGHT_HEX}'>orange</b> = right" in page
    assert page.count(f"stroke: {LEFT_HEX}") > 0 and page.count(f"stroke: {RIGHT_HEX}") > 0  # the figures too


def test_no_calibration_is_stated_in_the_report(kick: Path, tmp_path: Path) -> None:
    from zedo_cli.analysis.report.report import report_html

    page = report_html(analyse(read_result(kick)))
    assert "No decisive calls." in page and "no measure calibration for this prior" in page


def test_matplotlib_is_loaded_only_for_a_report(kick: Path) -> None:
    code = (
        "import sys\n"
        "from zedo_cli.analysis import analyse, write_csv\n"
        "from zedo_cli.formats.readers.result import read_result\n"
        f"write_csv(analyse(read_result({str(kick)!r})), '-')\n"
        "assert 'matplotlib' not in sys.modules\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.startswith("frame_index,")


def test_every_written_value_keeps_six_significant_digits(kick: Path) -> None:
    a = analyse(read_result(kick), AnalysisSettings(fps=30.0))
    written = {(r["frame_index"], r["person"], r["measure"]): r["value"] for r in rows_of(csv_text(a))}
    doc = analysis_document(a)
    by_json = {(r["frame_index"], r["person"], r["measure"]): r["value"] for r in doc["rows"]}
    checked = 0
    for r in a.rows:
        if isinstance(r.value, float) and np.isfinite(r.value) and r.value != 0:
            key = ("" if r.frame_index is None else str(r.frame_index), str(r.person), r.measure)
            assert float(written[key]) == pytest.approx(r.value, rel=5e-6, abs=0)
            assert by_json[(r.frame_index, r.person, r.measure)] == pytest.approx(r.value, rel=5e-6, abs=0)
            checked += 1
    assert checked > 100
    small = [r for r in a.rows if isinstance(r.value, float) and 0 < abs(r.value) < 0.05]
    assert small  # values below 0.05 exist (speeds, correlations near 0): three decimals would lose them


@pytest.mark.parametrize("fps", [None, 30.0])
def test_text_from_the_input_is_escaped_in_the_report(tmp_path: Path, fps: float | None) -> None:
    """Every text a result brings (its path, its input's path, its frames' file names) reaches the HTML escaped, in
    the image report and the clip report alike."""
    from zedo_cli.analysis.report.report import report_html

    evil = "<script>alert(1)</script>"
    doc = result_document(kicking_poses(60), fps=fps)
    doc["input"]["path"] = f"{evil}.json"
    for frame in doc["frames"]:
        frame["file_name"] = f"{evil}.png"
    folder = tmp_path / "<b>clips"
    folder.mkdir()
    page = report_html(analyse(read_result(write_document(folder / "<i>k.zedo.json", doc))))
    assert "<script" not in page and "<b>clips" not in page and "<i>k" not in page
    assert "&lt;i&gt;k.zedo.json" in page
