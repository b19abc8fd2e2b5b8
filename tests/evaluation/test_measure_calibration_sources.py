"""The frame measures' calibration recipe (benchmarks/calibrate/calibrate_measures.py) names each case's clip source
by its input kind and scores each source with a fit on the other source only."""

from __future__ import annotations

import numpy as np
from helpers import benchmark_module

recipe = benchmark_module("calibrate.calibrate_measures")


def cases(rng: np.random.Generator, n: int, adult_bias: float) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """`n` SyRIP image cases and `n` adult ones of the four symmetry pairs, the adult ones off by `adult_bias`."""
    kind = np.repeat(np.array(["gt", recipe.ADULT_SOURCE]), n)
    out = {}
    for name in recipe.SYMMETRY_NAMES:
        truth = rng.uniform(0.0, 60.0, 2 * n)
        raw = truth + rng.normal(0.0, 5.0, 2 * n) + np.where(kind == recipe.ADULT_SOURCE, adult_bias, 0.0)
        out[f"{name}|raw"], out[f"{name}|truth"], out[f"{name}|filled_raw"] = raw, truth, np.full(2 * n, np.nan)
    return out, kind


def test_cases_are_named_by_source_from_their_input_kind() -> None:
    kinds = np.array(["gt", "detected", "clips_gt", "near_clips_detected", "adult", "clips_adult"])
    assert list(recipe.source_of(kinds)) == ["SyRIP poses"] * 4 + ["adult motion"] * 2
    captures = recipe.source_of(np.array(["gt", "bandai", "cmu", "clips"]))
    assert list(captures) == ["SyRIP poses", "adult motion, Bandai-Namco", "adult motion, CMU and DeepMimic",
                              "SyRIP poses"]  # fmt: skip


def test_a_source_left_out_is_scored_by_the_other_sources_fit_and_a_biased_one_shows_it() -> None:
    rng = np.random.default_rng(0)
    got, kind = cases(rng, 400, 0.0)
    fold, group = np.zeros(len(kind), int), np.arange(len(kind))
    alike = recipe.pseudo_by_source(got, fold, kind, group, "none", 28.0)
    assert set(alike) == {"SyRIP poses", "adult motion"}
    assert all(0.8 <= row["all"]["coverage"] <= 1.0 for row in alike.values())
    got, kind = cases(rng, 400, 20.0)
    shifted = recipe.pseudo_by_source(got, fold, kind, group, "none", 28.0)
    assert shifted["adult motion"]["all"]["coverage"] < 0.3 and shifted["SyRIP poses"]["all"]["coverage"] < 0.8


def test_cases_are_cut_into_terciles_of_the_lifts_difficulty_within_each_source() -> None:
    kind = np.array(["gt"] * 6 + [recipe.ADULT_SOURCE] * 3 + ["gt"])
    difficulty = np.array([1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 30.0, 10.0, 20.0, np.nan])
    got = recipe.difficulty_terciles({recipe.DIFFICULTY: difficulty}, kind)
    assert list(got[:6]) == ["SyRIP poses, easiest third"] * 2 + ["SyRIP poses, middle third"] * 2 + [
        "SyRIP poses, hardest third"] * 2  # fmt: skip
    assert list(got[6:9]) == [
        "adult motion, hardest third",
        "adult motion, easiest third",
        "adult motion, middle third",
    ]
    assert got[9] == "SyRIP poses, unknown"


def test_the_syrip_clips_are_the_shipped_photo_orientation_ones_unless_supine_is_asked_for() -> None:
    from zedo_cli.evaluation.clips.cameras import trunk_axes
    from zedo_cli.evaluation.clips.eased import make_sequences

    rng = np.random.default_rng(0)
    poses = rng.normal(0.0, 0.15, (8, 12, 3))
    photo = recipe.syrip_clips(poses, np.random.default_rng(3), "photo")
    shipped = make_sequences(poses, np.random.default_rng(3), **recipe.CLIP_SETTINGS)
    np.testing.assert_array_equal(photo["xy"], shipped["xy"])
    supine = recipe.syrip_clips(poses, np.random.default_rng(3), "supine")
    axes, _ = trunk_axes(supine["cam"], recipe.SKELETON.joints)  # rows: left, up, forward
    assert np.median(-axes[:, 2, 2]) > 0.9  # the chest faces the camera (-z) in nearly every frame
