"""The `3d_` clip calibration's recipe (benchmarks/calibrate/features_3d_accuracy.py) scores each clip source with a
fit on the other sources only, and its known-camera range is the range of the clips it was fitted on."""

from __future__ import annotations

import numpy as np
from helpers import benchmark_module

recipe = benchmark_module("calibrate.features_3d_accuracy")
NAMES = np.array(["3d_mean_angle_LKnee", "3d_mean_angle_RKnee"])


def cases(rng: np.random.Generator, motion: str, bias: float, n: int = 60) -> dict[str, np.ndarray]:
    truth = rng.uniform(100.0, 170.0, (n, len(NAMES)))
    raw = truth + bias + rng.normal(0.0, 3.0, truth.shape)
    return {"names": NAMES, "raw": raw, "truth": truth, "motion": np.full(n, motion),
            "depth_m": rng.uniform(0.5, 3.2, n), "focal_px": rng.uniform(600, 3000, n)}  # fmt: skip


def fold(rng: np.random.Generator, adult_bias: float) -> dict[str, np.ndarray]:
    parts = [cases(rng, "positions", 0.0), cases(rng, "segments", 0.0), cases(rng, recipe.ADULT_SOURCE, adult_bias)]
    return {k: np.concatenate([p[k] for p in parts]) if k != "names" else NAMES for k in parts[0]}


def test_a_source_left_out_is_scored_by_the_others_fit_and_a_biased_one_shows_it() -> None:
    rng = np.random.default_rng(0)
    alike = recipe.held_out_by_source({0: fold(rng, 0.0), 1: fold(rng, 0.0)}, NAMES)
    assert set(alike) == {"SyRIP poses", "adult motion"}  # both motions of SyRIP's poses left out together
    assert all(0.8 <= cov["all"] <= 1.0 for cov in alike.values())
    shifted = recipe.held_out_by_source({0: fold(rng, 15.0), 1: fold(rng, 15.0)}, NAMES)
    assert shifted["adult motion"]["all"] < 0.2 and shifted["adult motion"]["mean_angle"] < 0.2


def test_the_known_camera_range_is_the_fitted_clips_range() -> None:
    rng = np.random.default_rng(1)
    got = {0: fold(rng, 0.0)}
    domain = recipe.camera_domain(got)
    assert domain.root_depth_m[0] == recipe.CAMERA_DEPTH_M[0]
    assert np.nanmax(got[0]["depth_m"]) <= domain.root_depth_m[1] <= recipe.CAMERA_DEPTH_M[1]
    assert domain.focal_px[0] <= got[0]["focal_px"].min() and domain.focal_px[1] >= got[0]["focal_px"].max()
