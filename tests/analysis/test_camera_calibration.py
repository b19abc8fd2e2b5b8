"""Measure calibrations for known cameras: a result lifted with `--focal` or
`--intrinsics` gets intervals where its poses lie inside a calibration's camera range, and each
measure says why not where they do not; pseudo-camera results are analysed as before."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from analysis_results import kicking_poses, result_document, write_document
from test_calibration import JOINTS, PARAMS, SHA, calibration

from zedo_cli.analysis.analyse import SYMMETRY_NAMES, analyse
from zedo_cli.analysis.uncertainty.calibration import (
    CameraDomain,
    MeasureCalibration,
    MeasureCalibrationEntry,
    assign_calibrations,
    read_calibrations,
    write_calibrations,
)
from zedo_cli.formats.readers.result import read_result

CLI = {**PARAMS, "camera_sources": ["cli"]}


def camera_calibration(depth: tuple[float, float], focal: tuple[float, float] = (600.0, 2500.0),
                       temporal: str = "none", width: float = 8.0) -> MeasureCalibration:  # fmt: skip
    """A calibration of known cameras: +-`width` degrees around the measured value, for `depth` and `focal`."""
    return replace(calibration(temporal, width=width), cameras=("cli", "file"), domain=CameraDomain(depth, focal))


def focal_result(tmp_path: Path, depth: float = 1.0, frames: int = 30, fps: float | None = None) -> Path:
    """Kicking poses `depth` metres from a camera of f = 1000 px given to the lift (`--focal`)."""
    poses = kicking_poses(frames) + np.array([0.0, 0.0, depth - 1.0])
    doc = result_document(poses, fps=fps)
    doc["params"].update({**CLI, "temporal": {"mode": "smooth" if fps else "none"}, "fps": fps})
    return write_document(tmp_path / "focal.zedo.json", doc)


def frame_rows(a, name: str) -> list:  # noqa: ANN001
    return [r for r in a.rows if r.measure == name and r.frame_index is not None]


def test_a_focal_result_in_the_calibrated_range_gets_intervals(tmp_path: Path) -> None:
    cals = [calibration(width=3.0), camera_calibration((0.6, 2.0))]  # the pseudo camera's first, as bundled
    a = analyse(read_result(focal_result(tmp_path)), calibrations=cals)
    assert a.uncertainty_available and a.calibration_note == "calibrated"
    for r in frame_rows(a, "symmetry_shank_deg"):  # the camera calibration's +-8, not the pseudo one's +-3
        assert r.how == "calibrated"
        assert r.high == pytest.approx(r.value + 8.0)
    assert {r.how for r in frame_rows(a, "left_knee_flexion_deg")} == {"calibrated"}


def test_outside_the_calibrated_range_each_measure_says_so(tmp_path: Path) -> None:
    cals = [camera_calibration((1.2, 2.0))]  # no pseudo camera's calibration to stand in
    a = analyse(read_result(focal_result(tmp_path, depth=1.0)), calibrations=cals)
    assert not a.uncertainty_available
    for name in (*SYMMETRY_NAMES, "right_hip_flexion_deg"):
        rows = frame_rows(a, name)
        assert all(np.isnan(r.low) for r in rows)
        assert {r.how for r in rows} == {
            "none: camera outside the calibrated range (root depth 1.00 m, focal length 1000 px; calibrated: "
            "root depth 1.2-2 m, focal length 600-2500 px)"}  # fmt: skip
    assert {r.call for r in frame_rows(a, "symmetry_thigh_deg")} == {"uncertain"}
    narrow_focal = [camera_calibration((0.6, 2.0), focal=(1500.0, 2500.0))]
    b = analyse(read_result(focal_result(tmp_path)), calibrations=narrow_focal)
    assert "focal length 1000 px" in frame_rows(b, "symmetry_thigh_deg")[0].how


def test_poses_are_matched_one_by_one_to_the_calibrated_depth_ranges(tmp_path: Path) -> None:
    near, far = camera_calibration((0.6, 1.2), width=4.0), camera_calibration((1.2, 2.0), width=9.0)
    depth = np.array([0.8, 1.5, 2.5, np.nan])
    got = assign_calibrations([near, far], CLI, JOINTS, depth, np.full(4, 1000.0))
    assert got.calibrations == (near, far) and got.index.tolist() == [0, 1, -1, -1] and got.stand_in == 0
    assert got.why_not[2].startswith("camera outside the calibrated range (root depth 2.50 m")
    assert "states no root depth" in got.why_not[3]
    pseudo = assign_calibrations([calibration(), near], PARAMS, JOINTS, depth, np.full(4, np.nan))
    assert pseudo.index.tolist() == [0, 0, 0, 0]  # the pseudo camera's calibration has no range: every pose


def test_outside_the_known_cameras_range_the_pseudo_cameras_calibration_stands_in(tmp_path: Path) -> None:
    """Stating the camera never loses a frame interval that leaving it out would give: where the stated camera lies
    outside every known camera calibration's range, the pseudo camera's calibration (matching but for the camera)
    holds, and a note says so."""
    pseudo, near, far = calibration(), camera_calibration((0.6, 1.2), width=4.0), camera_calibration((1.2, 2.0))
    depth = np.array([0.8, 1.5, 2.5, np.nan])
    got = assign_calibrations([pseudo, near, far], CLI, JOINTS, depth, np.full(4, 1000.0))
    assert got.calibrations == (near, far, pseudo) and got.index.tolist() == [0, 1, 2, -1] and got.stand_in == 1
    assert "states no root depth" in got.why_not[3]  # a pose whose camera cannot be checked gets none
    a = analyse(read_result(focal_result(tmp_path, depth=3.0)), calibrations=[pseudo, far])
    assert a.uncertainty_available and a.calibration_note == "calibrated"
    assert all(np.isfinite(r.low) for r in frame_rows(a, "symmetry_thigh_deg"))
    assert any("the pseudo camera's calibration stands in" in n for n in a.notes)
    pseudo_result = assign_calibrations([pseudo, far], PARAMS, JOINTS, depth, np.full(4, np.nan))
    assert pseudo_result.stand_in == 0 and pseudo_result.index.tolist() == [0, 0, 0, 0]


def test_a_root_frame_result_without_its_root_depth_says_why(tmp_path: Path) -> None:
    res = read_result(focal_result(tmp_path))
    res = replace(res, coordinate_frame="root", root_translation=None)
    a = analyse(res, calibrations=[camera_calibration((0.6, 2.0))])
    assert "states no root depth or camera" in frame_rows(a, "symmetry_shank_deg")[0].how


def test_pseudo_camera_results_are_analysed_as_before(tmp_path: Path) -> None:
    doc = result_document(kicking_poses(20))
    doc["params"].update(PARAMS)
    path = write_document(tmp_path / "p.zedo.json", doc)
    alone = analyse(read_result(path), calibrations=[calibration(width=3.0)])
    both = analyse(read_result(path), calibrations=[calibration(width=3.0), camera_calibration((0.6, 2.0))])
    keep = ("measure", "value", "low", "high", "call", "interval", "call_low", "call_high")

    def cells(rows: list) -> list[list]:  # NaN as None: NaN != NaN
        return [[None if isinstance(v, float) and v != v else v for v in (getattr(r, c) for c in keep)] for r in rows]

    assert cells(alone.rows) == cells(both.rows)
    cli = analyse(read_result(path), calibrations=[calibration()])  # and a pseudo result never takes a camera one
    assert cli.calibration_note == "calibrated"
    only_camera = analyse(read_result(path), calibrations=[camera_calibration((0.6, 2.0))])
    assert only_camera.calibration_note == "no measure calibration for this camera (calibrated: cli, file)"


def test_a_calibration_with_a_camera_range_reads_back_and_one_without_writes_as_before(tmp_path: Path) -> None:
    pseudo, cam = calibration(), camera_calibration((0.6, 2.0))
    assert "domain" not in MeasureCalibrationEntry.of(pseudo).model_dump()
    assert MeasureCalibrationEntry.of(cam).model_dump()["domain"] == {
        "root_depth_m": [0.6, 2.0],
        "focal_px": [600.0, 2500.0],
    }
    path = tmp_path / "m.json"
    write_calibrations(path, [pseudo, cam])
    assert read_calibrations(path) == [pseudo, cam]
    assert cam.prior_sha256 == SHA


def test_a_joint_filled_by_the_prior_takes_the_calibrations_wider_model_where_it_has_one(tmp_path: Path) -> None:
    from test_calibration import document

    from zedo_cli.analysis.uncertainty.calibration import LEVELS, MeasureModel

    doc = document(kicking_poses(3))
    doc["params"].update(CLI)
    doc["frames"][0]["persons"][0]["observed"][JOINTS.index("left_wrist")] = False
    path = write_document(tmp_path / "k.zedo.json", doc)
    wide = {lv: (20.0,) for lv in LEVELS}
    cal = camera_calibration((0.6, 2.0))
    cal = replace(cal, filled={n: MeasureModel(20.0, 1.0, (), wide, wide, circular=False) for n in cal.measures})
    a = analyse(read_result(path), calibrations=[cal])
    forearm = frame_rows(a, "symmetry_forearm_deg")
    assert forearm[0].how == "calibrated_filled: left_wrist"
    assert forearm[0].high == pytest.approx(forearm[0].value + 20.0)
    assert forearm[1].how == "calibrated" and forearm[1].high == pytest.approx(forearm[1].value + 8.0)
    p = [r.value for r in a.rows if r.measure == "symmetry_forearm_probability_asymmetric"]
    assert all(np.isfinite(p))  # the filled frame has a probability too
    without = analyse(read_result(path), calibrations=[camera_calibration((0.6, 2.0))])  # no such model: none
    assert frame_rows(without, "symmetry_forearm_deg")[0].how.startswith("none: joint filled by the prior")
    path2 = tmp_path / "m.json"
    write_calibrations(path2, [cal])
    assert read_calibrations(path2) == [cal]


def test_ranges_that_meet_read_as_one_and_a_near_pose_takes_the_near_range() -> None:
    near, main = camera_calibration((0.4, 0.6), width=12.0), camera_calibration((0.6, 2.0))
    depth = np.array([0.45, 0.6, 1.0, 0.3, 2.2])
    got = assign_calibrations([near, main], CLI, JOINTS, depth, np.full(5, 1000.0))
    assert got.index.tolist() == [0, 0, 1, -1, -1]  # the first that holds the pose: 0.6 m is the near range's end
    assert got.why_not[3] == ("camera outside the calibrated range (root depth 0.30 m, focal length 1000 px; "
                              "calibrated: root depth 0.4-2 m, focal length 600-2500 px)")  # fmt: skip
    apart = camera_calibration((1.2, 2.0))  # ranges that do not meet are named one by one
    why = assign_calibrations([near, apart], CLI, JOINTS, np.array([1.0]), np.array([1000.0])).why_not[0]
    assert why.endswith("calibrated: root depth 0.4-0.6 m, focal length 600-2500 px; root depth 1.2-2 m, "
                        "focal length 600-2500 px)")  # fmt: skip


def test_the_bundled_camera_calibrations_cover_lifted_root_depths_of_0_4_to_3_5_m() -> None:
    """Each mode's calibrations of known cameras meet end to end over 0.4-3.5 m and 600-3000 px (the distances and
    lenses clinics use), each range fitted on its own held-out cases of both clip sources with a model for every
    symmetry pair, observed and with a filled joint; the pseudo camera's have no range, and models of filled joints
    too (the target: an interval for every symmetry value of a clip at f = 1000 px about 1 m away, and of one 3 m
    away at 3000 px, and for the same values without the camera stated)."""
    from zedo_cli.analysis.uncertainty.calibration import bundled_calibrations, describe_domains

    frames = [c for c in bundled_calibrations() if c.scope == "frames"]
    assert all(c.domain is None for c in frames if c.cameras == ("pseudo",))
    for mode in ("none", "smooth", "clip"):  # frame by frame, --temporal smooth and --temporal clip
        pseudo = [c for c in frames if c.cameras == ("pseudo",) and c.temporal_mode == mode]
        assert len(pseudo) == 1 and pseudo[0].provenance["sources"] == ["SyRIP poses", "adult motion"]
        # a frame with a joint the prior filled gets an interval whether the camera is stated or not
        assert set(SYMMETRY_NAMES) <= set(pseudo[0].filled) and pseudo[0].provenance["cases_filled"] >= 100
        if mode != "none":
            assert set(pseudo[0].filled) == set(pseudo[0].measures)
        known = sorted((c for c in frames if c.cameras == ("cli", "file") and c.temporal_mode == mode),
                       key=lambda c: c.domain.root_depth_m)  # fmt: skip
        assert [c.domain.root_depth_m for c in known] == [(0.4, 0.6), (0.6, 2.0), (2.0, 3.5)]
        assert describe_domains([c.domain for c in known]) == "root depth 0.4-3.5 m, focal length 600-3000 px"
        assert all("adult motion" in c.provenance["sources"] for c in known if c.domain.root_depth_m[0] >= 0.6)
        for c in known:
            assert set(SYMMETRY_NAMES) <= set(c.measures) and set(SYMMETRY_NAMES) <= set(c.filled)
            assert c.provenance["cases"] >= 1000 and c.provenance["cases_filled"] >= 100


def test_the_recipe_replaces_every_range_of_a_mode_and_leaves_the_pseudo_cameras_in_place() -> None:
    from helpers import benchmark_module

    replace_calibrations = benchmark_module("calibrate.calibrate_measures").replace_calibrations

    pseudo, clips = calibration(), replace(calibration("smooth"), scope="clips")
    old = [pseudo, camera_calibration((0.6, 2.0)), camera_calibration((0.6, 2.0), temporal="smooth"), clips]
    new = [camera_calibration((0.4, 0.6), width=12.0), camera_calibration((0.6, 2.0), width=9.0),
           camera_calibration((0.4, 0.6), temporal="smooth", width=12.0),
           camera_calibration((0.6, 2.0), temporal="smooth", width=9.0)]  # fmt: skip
    merged = replace_calibrations(old, new)
    assert merged == [pseudo, *new, clips]  # the old ranges gone, whatever they were; the others where they were
    assert merged[0] is pseudo and merged[-1] is clips
    assert replace_calibrations(old, []) == old
    assert replace_calibrations([pseudo], new[:1]) == [pseudo, new[0]]


def test_a_filled_joint_outside_the_calibrated_range_gives_the_cameras_reason(tmp_path: Path) -> None:
    """A pose outside every range gets no interval because of its camera, filled joint or not: the `interval`
    column names the camera, not the filled joint (the calibration has a model of filled joints inside)."""
    from test_calibration import document

    from zedo_cli.analysis.uncertainty.calibration import LEVELS, MeasureModel

    doc = document(kicking_poses(2) + np.array([0.0, 0.0, -0.7]))  # 0.3 m from the camera
    doc["params"].update(CLI)
    doc["frames"][0]["persons"][0]["observed"][JOINTS.index("left_wrist")] = False
    wide = {lv: (20.0,) for lv in LEVELS}
    cal = camera_calibration((0.4, 2.0))
    cal = replace(cal, filled={n: MeasureModel(20.0, 1.0, (), wide, wide, circular=False) for n in cal.measures})
    forearm = frame_rows(analyse(read_result(write_document(tmp_path / "k.zedo.json", doc)), calibrations=[cal]),
                         "symmetry_forearm_deg")  # fmt: skip
    why = ("none: camera outside the calibrated range (root depth 0.30 m, focal length 1000 px; calibrated: root "
           "depth 0.4-2 m, focal length 600-2500 px)")  # fmt: skip
    assert [r.how for r in forearm] == [why, why]  # the first with a filled wrist, the second without
    assert all(np.isnan(r.low) for r in forearm)


def test_the_report_keeps_every_calibration_warning(tmp_path: Path) -> None:
    from zedo_cli.analysis.report.report import report_html

    # frames 0-14 at 1.0 m, 15-29 at 2.5 m: half the poses lie outside the calibrated depths
    poses = kicking_poses(30)
    poses[15:] += np.array([0.0, 0.0, 1.5])
    doc = result_document(poses)
    doc["params"].update({**CLI, "temporal": {"mode": "none"}})
    a = analyse(read_result(write_document(tmp_path / "half.zedo.json", doc)),
                calibrations=[camera_calibration((0.6, 2.0))])  # fmt: skip
    partly = "15 of 30 poses have no calibrated intervals"
    assert a.uncertainty_available and any(n.startswith(partly) for n in a.notes)
    assert partly in report_html(a)
    none = analyse(read_result(focal_result(tmp_path, depth=3.0)), calibrations=[camera_calibration((0.6, 2.0))])
    page = report_html(none)
    assert not none.uncertainty_available and "No decisive calls" in page
    assert page.count("no calibrated intervals: camera outside the calibrated range") == 0  # said in the decisions
