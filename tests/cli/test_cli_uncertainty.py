"""`zedo lift` with hypotheses and calibrated per-joint uncertainty: what the output
carries, when, and what it says when there is no calibration."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from test_cli import lift_args, runner, write_coco

from zedo_cli.cli import app
from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.lifting.config import get_preset
from zedo_cli.lifting.uncertainty import UncertaintyModel, calibration_settings, write_calibrations
from zedo_cli.prior.weights import file_sha256

JOINTS = get_skeleton("syrip12").joints


def _calibration(tmp_path: Path, prior: Path, hypotheses: int, scale: float = 2.0) -> Path:
    cfg = replace(get_preset("fast"), steps=30, hypotheses=hypotheses)
    model = UncertaintyModel(file_sha256(prior), calibration_settings(cfg), 0.9, JOINTS,
                             np.full(12, 0.01), np.full(12, scale), {"data": "test"})  # fmt: skip
    path = tmp_path / "cal.json"
    write_calibrations(path, [model])
    return path


def _lift(prior: Path, src: Path, *extra: str) -> dict:
    result = runner.invoke(app, lift_args(prior, str(src), "-o", "-", *extra))
    assert result.exit_code == 0, result.output
    return json.loads(result.stdout)


def test_no_calibration_for_the_prior_means_no_uncertainty_and_says_why(tiny_prior_path: Path, tmp_path: Path) -> None:
    doc = _lift(tiny_prior_path, write_coco(tmp_path / "kp.json"))
    assert doc["params"]["uncertainty"] == {"uncertainty_m": False, "coverage": None,
                                            "note": "no uncertainty calibration for this prior"}  # fmt: skip
    assert all("uncertainty_m" not in p for f in doc["frames"] for p in f["persons"])


def test_a_matching_calibration_gives_radii_from_the_spread(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json")
    cal = _calibration(tmp_path, tiny_prior_path, hypotheses=4)
    doc = _lift(tiny_prior_path, src, "--hypotheses", "4", "--calibration", str(cal), "--save-hypotheses")
    assert doc["params"]["uncertainty"]["uncertainty_m"] is True and doc["params"]["hypotheses"] == 4
    person = doc["frames"][0]["persons"][0]
    radii = np.array(person["uncertainty_m"])
    hyps = np.array(person["hypotheses_m"])
    assert hyps.shape == (4, 12, 3) and radii.shape == (12,)
    reported = np.array(person["keypoints_3d_root_relative"])
    spread = np.sqrt(((hyps - reported) ** 2).sum(-1).mean(0))
    np.testing.assert_allclose(radii, 2.0 * (spread + 0.01), atol=2e-4)  # scale * (spread + floor), 4 digits


def test_settings_other_than_the_calibrated_ones_get_no_uncertainty(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json")
    cal = _calibration(tmp_path, tiny_prior_path, hypotheses=4)
    doc = _lift(tiny_prior_path, src, "--hypotheses", "2", "--calibration", str(cal))
    assert doc["params"]["uncertainty"]["uncertainty_m"] is False
    assert "--hypotheses 4" in doc["params"]["uncertainty"]["note"]
    assert "hypotheses_m" not in doc["frames"][0]["persons"][0]  # kept only with --save-hypotheses


def test_one_hypothesis_has_a_constant_calibrated_radius(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json")
    cal = _calibration(tmp_path, tiny_prior_path, hypotheses=1)
    doc = _lift(tiny_prior_path, src, "--hypotheses", "1", "--calibration", str(cal))
    radii = [p["uncertainty_m"] for f in doc["frames"] for p in f["persons"]]
    assert np.allclose(radii, 0.02)


def test_the_same_seed_gives_the_same_hypotheses_and_another_seed_others(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json")
    a, b, c = (_lift(tiny_prior_path, src, "--hypotheses", "3", "--save-hypotheses", "--seed", s) for s in "112")
    pick = lambda d: [p["hypotheses_m"] for f in d["frames"] for p in f["persons"]]  # noqa: E731
    assert pick(a) == pick(b) and pick(a) != pick(c)


def test_a_broken_calibration_file_is_refused_before_any_work(tiny_prior_path: Path, tmp_path: Path) -> None:
    bad = tmp_path / "cal.json"
    bad.write_text('{"format": "something else"}')
    result = runner.invoke(app, lift_args(tiny_prior_path, str(write_coco(tmp_path / "kp.json")), "-o", "-",
                                          "--calibration", str(bad)))  # fmt: skip
    assert result.exit_code != 0 and "cal.json" in result.output and "Traceback" not in result.output


def test_hypotheses_out_of_range_are_usage_errors(tiny_prior_path: Path, tmp_path: Path) -> None:
    for k in ("0", "65"):
        result = runner.invoke(
            app, lift_args(tiny_prior_path, str(write_coco(tmp_path / "kp.json")), "--hypotheses", k)
        )
        assert result.exit_code == 2 and "--hypotheses" in result.output


def test_every_writer_carries_the_uncertainty(tiny_prior_path: Path, tmp_path: Path) -> None:
    from zedo_cli.formats.readers.result import read_result

    src = write_coco(tmp_path / "kp.json")
    cal = _calibration(tmp_path, tiny_prior_path, hypotheses=2)
    radii = {}
    for ext in ("json", "jsonl", "csv", "npz"):
        out = tmp_path / f"out.{ext}"
        args = lift_args(tiny_prior_path, str(src), "-o", str(out), "--hypotheses", "2", "--calibration", str(cal),
                         "--save-hypotheses")  # fmt: skip
        result = runner.invoke(app, args)
        assert result.exit_code == 0, result.output
        radii[ext] = read_result(out).uncertainty_m
        assert radii[ext] is not None and radii[ext].shape == (3, 12) and np.isfinite(radii[ext]).all()
    for ext in ("jsonl", "csv", "npz"):
        np.testing.assert_allclose(radii[ext], radii["json"], atol=1e-4)
    with np.load(tmp_path / "out.npz") as data:
        assert data["hypotheses"].shape == (3, 2, 12, 3)


@pytest.mark.parametrize("option", ["twin_rate", "proportion_rate"])
def test_length_rates_are_bounded_and_other_rates_are_not_calibrated(
    option: str, tiny_prior_path: Path, tmp_path: Path
) -> None:
    flag = "--" + option.replace("_", "-")
    src = write_coco(tmp_path / "kp.json")
    for bad in ("-0.1", "1.5", "nan"):
        result = runner.invoke(app, lift_args(tiny_prior_path, str(src), flag, bad))
        assert result.exit_code == 2 and flag in result.output
    cal = _calibration(tmp_path, tiny_prior_path, hypotheses=1)
    assert _lift(tiny_prior_path, src, "--calibration", str(cal))["params"]["uncertainty"]["uncertainty_m"] is True
    doc = _lift(tiny_prior_path, src, flag, "0", "--calibration", str(cal))
    assert doc["params"]["config"][option] == 0.0 and doc["params"]["uncertainty"]["uncertainty_m"] is False


def test_twin_ratio_cap_is_zero_or_at_least_one_and_other_caps_are_not_calibrated(
    tiny_prior_path: Path, tmp_path: Path
) -> None:
    src = write_coco(tmp_path / "kp.json")
    for bad in ("0.5", "-1", "nan", "1000"):
        result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "--twin-ratio-cap", bad))
        assert result.exit_code == 2 and "--twin-ratio-cap" in result.output
    cal = _calibration(tmp_path, tiny_prior_path, hypotheses=1)
    for cap in ("0", "1.2"):
        doc = _lift(tiny_prior_path, src, "--twin-ratio-cap", cap, "--calibration", str(cal))
        assert doc["params"]["config"]["twin_ratio_cap"] == float(cap)
        assert doc["params"]["uncertainty"]["uncertainty_m"] is False


@pytest.mark.parametrize(
    ("option", "field", "bad_values", "other"),
    [
        ("--ray-weight", "ray_weight", ("0", "-0.1", "1.5", "nan"), 1.0),
        ("--ray-confidence-ratio", "ray_confidence_ratio", ("-0.1", "1.5", "nan"), 0.0),
        ("--hip-ray-factor", "hip_ray_factor", ("-0.1", "1.5", "nan"), 1.0),
    ],
)
def test_ray_pull_options_are_bounded_and_other_values_are_not_calibrated(
    tiny_prior_path: Path, tmp_path: Path, option: str, field: str, bad_values: tuple[str, ...], other: float
) -> None:
    src = write_coco(tmp_path / "kp.json")
    for bad in bad_values:
        result = runner.invoke(app, lift_args(tiny_prior_path, str(src), option, bad))
        assert result.exit_code == 2 and option in result.output
    cal = _calibration(tmp_path, tiny_prior_path, hypotheses=1)
    doc = _lift(tiny_prior_path, src, option, str(other), "--calibration", str(cal))
    assert doc["params"]["config"][field] == other and doc["params"]["uncertainty"]["uncertainty_m"] is False


def test_hypotheses_give_each_person_their_spread_and_flag_an_unstable_one(
    tiny_prior_path: Path, tmp_path: Path
) -> None:
    from zedo_cli.lifting.result import UNSTABLE_SPREAD_M

    src = write_coco(tmp_path / "kp.json", n=4)
    doc = _lift(tiny_prior_path, src, "--hypotheses", "3", "--save-hypotheses")
    persons = [p for f in doc["frames"] for p in f["persons"]]
    for person in persons:
        hyps = np.array(person["hypotheses_m"])
        reported = np.array(person["keypoints_3d_root_relative"])
        spread_mm = np.sqrt(((hyps - reported) ** 2).sum(-1).mean(0)).max() * 1000  # the most different joint
        assert person["hypothesis_spread_mm"] == pytest.approx(spread_mm, abs=0.06)
        assert ("unstable_solution" in person["flags"]) == (spread_mm > UNSTABLE_SPREAD_M * 1000)
    assert all("hypothesis_spread_mm" not in p for f in _lift(tiny_prior_path, src)["frames"] for p in f["persons"])
    # the other formats: a CSV column, NPZ arrays
    for ext in ("csv", "npz"):
        result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "-o", str(tmp_path / f"r.{ext}"),
                                              "--hypotheses", "3"))  # fmt: skip
        assert result.exit_code == 0, result.output
    header = (tmp_path / "r.csv").read_text().splitlines()[0].split(",")
    assert header[-1] == "hypothesis_spread_mm"
    npz = np.load(tmp_path / "r.npz")
    np.testing.assert_allclose(npz["hypothesis_spread_mm"], [p["hypothesis_spread_mm"] for p in persons], atol=0.06)
    assert npz["unstable_solution"].tolist() == ["unstable_solution" in p["flags"] for p in persons]
