"""The split-conformal uncertainty model (lifting/uncertainty.py): its coverage, its matching to
a prior and settings, and its file."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from zedo_cli.errors import WeightsError
from zedo_cli.lifting.config import get_preset
from zedo_cli.lifting.uncertainty import (
    conformal_scale,
    find_model,
    fit_model,
    joint_spread,
    radius_m,
    read_calibrations,
    write_calibrations,
)
from zedo_cli.stats import TooFewCases

JOINTS = tuple(f"j{i}" for i in range(3))
FAST = get_preset("fast")


def test_conformal_scale_is_the_finite_sample_quantile() -> None:
    scores = np.arange(1, 11, dtype=float)  # n = 10: rank ceil(11 * 0.9) = 10
    assert conformal_scale(scores, 0.9) == 10.0
    assert conformal_scale(np.arange(1, 101, dtype=float), 0.9) == 91.0  # ceil(101 * 0.9) = 91
    assert conformal_scale(np.array([np.nan, 2.0, 1.0]), 0.5) == 2.0  # NaN ignored; ceil(4 * 0.5) = 2


def test_too_few_scores_back_no_radius() -> None:
    # 8 scores cannot back a 90 % quantile (rank ceil(9 * 0.9) = 9): refused, never the largest score
    with pytest.raises(TooFewCases, match="left_knee: too few calibration cases \\(8; a 0.9 quantile needs 9\\)"):
        conformal_scale(np.arange(1, 9, dtype=float), 0.9, "left_knee")


@pytest.mark.parametrize("hypotheses", [1, 8])
def test_radii_fitted_on_one_half_cover_90_percent_of_the_other(hypotheses: int) -> None:
    rng = np.random.default_rng(0)
    n = 4000
    spread = rng.gamma(2.0, 0.01, size=(n, 3)) if hypotheses > 1 else np.zeros((n, 3))
    error = (spread + 0.02) * np.abs(rng.normal(size=(n, 3))) * 2.0  # error grows with the spread
    cfg = replace(FAST, hypotheses=hypotheses)
    model = fit_model(error[: n // 2], spread[: n // 2], coverage=0.9, prior_sha256="x", cfg=cfg, joints=JOINTS,
                      provenance={})  # fmt: skip
    inside = error[n // 2 :] <= radius_m(model, spread[n // 2 :])
    assert 0.88 <= inside.mean() <= 0.92
    assert ((inside.mean(0) > 0.86) & (inside.mean(0) < 0.94)).all()  # per joint too


def test_spread_is_the_rms_distance_of_the_hypotheses() -> None:
    reported = np.zeros((1, 2, 3))
    hyps = np.zeros((1, 4, 2, 3))
    hyps[0, :, 0, 0] = [0.0, 0.1, -0.1, np.nan]  # a NaN hypothesis is left out
    np.testing.assert_allclose(joint_spread(hyps, reported), [[np.sqrt(0.02 / 3), 0.0]])
    assert (joint_spread(None, reported) == 0).all()


def test_a_model_holds_only_for_its_prior_and_settings(tmp_path: Path) -> None:
    error, spread = np.full((20, 3), 0.05), np.zeros((20, 3))
    model = fit_model(error, spread, coverage=0.9, prior_sha256="abc", cfg=FAST, joints=JOINTS, provenance={})
    path = tmp_path / "cal.json"
    write_calibrations(path, [model])
    models = read_calibrations(path)
    assert find_model(models, "abc", JOINTS, FAST)[0] == models[0]
    assert find_model(models, "abc", JOINTS, replace(FAST, chunk_size=7, bf16=True))[0] is not None  # same poses
    assert find_model(models, "other", JOINTS, FAST) == (None, "no uncertainty calibration for this prior")
    none, why = find_model(models, "abc", JOINTS, replace(FAST, steps=10))
    assert none is None and "--hypotheses 1" in why


def test_a_calibration_predating_a_setting_holds_for_its_default_only() -> None:
    """A calibration written before `length_iterations` existed was made with its default (1): it
    holds for the default and not for another value; a setting it names that LiftConfig lacks
    never matches."""
    error, spread = np.full((20, 3), 0.05), np.zeros((20, 3))
    one = replace(FAST, length_iterations=1)
    model = fit_model(error, spread, coverage=0.9, prior_sha256="abc", cfg=one, joints=JOINTS, provenance={})
    older = replace(model, settings={k: v for k, v in model.settings.items() if k != "length_iterations"})
    assert find_model([older], "abc", JOINTS, one)[0] is older
    assert find_model([older], "abc", JOINTS, replace(FAST, length_iterations=2))[0] is None
    unknown = replace(model, settings={**model.settings, "a_future_setting": 1})
    assert find_model([unknown], "abc", JOINTS, one)[0] is None


def test_a_file_of_another_kind_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "cal.json"
    path.write_text("[1, 2]")
    with pytest.raises(WeightsError, match="cal.json"):
        read_calibrations(path)


def test_the_bundled_calibration_matches_the_bundled_prior_and_the_default_preset() -> None:
    from zedo_cli.lifting.uncertainty import bundled_calibrations
    from zedo_cli.prior.weights import file_sha256, resolve_prior_path

    sha = file_sha256(resolve_prior_path(None))
    models = bundled_calibrations()
    joints = models[0].joints
    for k in (1, 8):
        model, why = find_model(models, sha, joints, replace(FAST, hypotheses=k))
        assert model is not None, why
        cover = model.provenance["cross_fitted_coverage"]
        assert all(0.85 <= cover[kind]["all"] <= 0.95 for kind in ("gt", "detected"))
    assert find_model(models, sha, joints, get_preset("faithful"))[0] is None


def test_an_instance_without_usable_hypotheses_has_nan_spread_and_no_warning() -> None:
    import warnings

    hyps = np.full((2, 3, 2, 3), np.nan)
    hyps[0] = 0.0  # instance 1 was not lifted: all its hypotheses are NaN
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # numpy's empty-slice warning would reach a user's stderr
        spread = joint_spread(hyps, np.zeros((2, 2, 3)))
    assert (spread[0] == 0).all() and np.isnan(spread[1]).all()
