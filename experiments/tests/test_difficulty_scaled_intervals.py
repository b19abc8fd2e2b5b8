"""The rejected difficulty-scaled intervals of experiments/difficulty_scaled_intervals.py do what their docs say:
where the residual grows with the difficulty, a positive scale is chosen and the intervals hold in the hard cases
as in the easy ones; where it does not, the shipped constant width (c = 0) stays."""

from __future__ import annotations

import numpy as np

from experiments.difficulty_scaled_intervals import DIFFICULTY, scaled_fit, score


def _cases(rng: np.random.Generator, grows: bool, n: int = 4000) -> dict[str, np.ndarray]:
    d = rng.uniform(0.0, 10.0, n)
    truth = rng.uniform(0.0, 60.0, n)
    raw = truth + rng.normal(0.0, 1.0, n) * (1.0 + 0.4 * d if grows else 3.0)  # c = 0.4 is on the grid
    return {"symmetry_thigh_deg|raw": raw, "symmetry_thigh_deg|truth": truth, DIFFICULTY: d}


def test_a_residual_growing_with_the_difficulty_gets_a_scale_and_holds_in_hard_cases() -> None:
    rng = np.random.default_rng(0)
    fit, test = _cases(rng, True), _cases(rng, True)
    f = scaled_fit(fit["symmetry_thigh_deg|raw"], fit["symmetry_thigh_deg|truth"], fit[DIFFICULTY], False, 2)
    assert f["c"] > 0
    hard = test[DIFFICULTY] > 7.0
    inside, count, _ = score({"symmetry_thigh_deg": f}, test, hard)
    assert 0.85 <= inside / count <= 0.95


def test_a_constant_residual_keeps_the_constant_width() -> None:
    rng = np.random.default_rng(1)
    fit = _cases(rng, False)
    f = scaled_fit(fit["symmetry_thigh_deg|raw"], fit["symmetry_thigh_deg|truth"], fit[DIFFICULTY], False, 2)
    assert f["c"] == 0.0
