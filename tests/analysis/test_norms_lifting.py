"""`zedo norms` and `--norms` compare what was measured: a clip feature's raw value where a calibration gave
an estimate (so that a reference and a clip compare alike whichever calibration held for each), and each
reference clip records how its result was lifted, so that a clip lifted otherwise gets a note."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
from analysis_results import kicking_poses, write_document
from test_calibration import calibration, document
from test_clip_calibration import KNEE, clip_calibration
from test_norms import VERSION, _reference

from zedo_cli.analysis.analyse import AnalysisSettings, analyse
from zedo_cli.analysis.compare import compared, features_by_person, lifting_mismatch, lifting_of
from zedo_cli.analysis.norms.norms import build_norms
from zedo_cli.analysis.norms.norms_file import read_norms, write_norms
from zedo_cli.analysis.report.clip_report import comparison_block
from zedo_cli.formats.readers.result import read_result
from zedo_cli.lifting.config import LiftConfig

# as the test documents record (test_calibration.PARAMS: the faithful preset's settings)
SMOOTH_PSEUDO = {"prior": {"sha256": "ab" * 32}, "config": LiftConfig().to_dict(), "temporal": {"mode": "smooth"},
                 "camera_sources": ["pseudo"]}  # fmt: skip


def _analysed(tmp_path: Path, calibrations: list) -> object:
    doc = document(kicking_poses(90), fps=30.0, temporal="smooth")
    return analyse(read_result(write_document(tmp_path / "k.zedo.json", doc)), AnalysisSettings(),
                   calibrations=calibrations)  # fmt: skip


def test_a_reference_and_a_clip_compare_what_was_measured(tmp_path: Path) -> None:
    calibrated = _analysed(tmp_path, [calibration("smooth", width=5.0), clip_calibration()])
    plain = _analysed(tmp_path, [])
    rows = {r.measure: r for r in calibrated.rows if r.frame_index is None}
    assert rows[KNEE].how == "calibrated" and rows[KNEE].value != rows[KNEE].raw_value  # shrunk
    median = rows["symmetry_forearm_median_deg"]
    assert np.isfinite(median.raw_value)
    (with_cal,), (without,) = features_by_person(calibrated), features_by_person(plain)
    assert with_cal.values[KNEE] == rows[KNEE].raw_value == without.values[KNEE]
    assert with_cal.values["symmetry_forearm_median_deg"] == median.raw_value
    assert without.values["symmetry_forearm_median_deg"] == median.raw_value  # uncalibrated: the value is the raw


def test_how_a_result_was_lifted_in_words() -> None:
    from zedo_cli.lifting.config import get_preset

    fast = {**SMOOTH_PSEUDO, "config": get_preset("fast").to_dict()}
    assert lifting_of(fast) == "prior abababababab, preset fast, temporal smooth, pseudo camera"
    faithful = {**fast, "config": get_preset("faithful").to_dict(), "temporal": {}, "camera_sources": ["cli"]}
    assert lifting_of(faithful) == "prior abababababab, preset faithful, temporal none, known camera"
    tuned = {**fast, "config": {**get_preset("fast").to_dict(), "steps": 7}}
    assert lifting_of(tuned) == "prior abababababab, other settings, temporal smooth, pseudo camera"
    assert lifting_of({}) == "prior unknown, unknown settings, temporal none, unknown camera"


def test_a_clip_lifted_otherwise_than_the_reference_gets_a_note(tmp_path: Path) -> None:
    pseudo = lifting_of(SMOOTH_PSEUDO)
    norms = build_norms([replace(c, lifting=pseudo) for c in _reference()], VERSION)
    write_norms(tmp_path / "norms.json", norms)
    back = read_norms(tmp_path / "norms.json", VERSION)
    assert {c.lifting for c in back.clips} == {pseudo}
    assert lifting_mismatch(back, pseudo) is None
    known = lifting_of({**SMOOTH_PSEUDO, "camera_sources": ["file"]})
    note = lifting_mismatch(back, known)
    assert note == (f"the reference's clips were lifted with {pseudo}, this clip with {known}: its 3D features "
                    "(3d_, symmetry medians) are compared with ones measured otherwise; lift the reference and "
                    "the clip alike")  # fmt: skip
    assert lifting_mismatch(build_norms(_reference(), VERSION), known) is None  # a reference that does not say
    a = _analysed(tmp_path, [])  # the test result: the test prior, --temporal smooth, the pseudo camera
    assert lifting_of(a.result.params) == pseudo
    assert not any(n.startswith("the reference's clips were lifted") for n in compared(a, back, None).notes)
    other = build_norms([replace(c, lifting=known) for c in _reference()], VERSION)
    a = compared(a, other, None)
    assert a.notes[-1] == lifting_mismatch(other, pseudo)
    block = comparison_block(a)  # the report's summary says it beside the comparison, not only in the notes
    assert block.startswith("<div class='note warn'>The reference&#x27;s clips were lifted with prior ")


def test_zedo_norms_says_when_its_clips_were_lifted_in_several_ways(tmp_path: Path) -> None:
    from typer.testing import CliRunner

    from zedo_cli.cli import app
    from zedo_cli.version import __version__

    rng = np.random.default_rng(4)
    paths = []
    for i in range(20):
        doc = document(kicking_poses(90) + rng.normal(0.0, 0.004, (90, 12, 3)), fps=30.0, temporal="smooth")
        doc["params"]["camera_sources"] = ["pseudo"] if i < 12 else ["cli"]
        paths.append(str(write_document(tmp_path / f"c{i}.zedo.json", doc)))
    result = CliRunner().invoke(app, ["norms", *paths, "-o", str(tmp_path / "norms.json")])
    assert result.exit_code == 0, result.output
    assert (
        "zedo: note: the clips were lifted in 2 ways (prior abababababab, preset faithful, temporal smooth, known"
        in (" ".join(result.output.split()))
    )
    norms = read_norms(tmp_path / "norms.json", __version__)
    assert [c.lifting.endswith("pseudo camera") for c in norms.clips] == [True] * 12 + [False] * 8
    assert {c.seconds for c in norms.clips} == {3.0}  # 90 frames at 30 fps
