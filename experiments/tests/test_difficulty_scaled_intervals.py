"""The rejected difficulty-scaled intervals of experiments/difficulty_scaled_intervals.py do what their docs say:
where the residual grows with the difficulty, a positive scale is chosen and the intervals hold in the hard cases
as in the easy ones; where it does not, the shipped constant width (c = 0) stays."""

from __future__ import annotations

import numpy as np

from benchmarks.calibrate.calibrate_measures import SKELETON
from experiments.difficulty_scaled_intervals import C_GRID, DIFFICULTY, foreshortening, scaled_fit, score

GRID = C_GRID["reprojection"]


def _cases(rng: np.random.Generator, grows: bool, n: int = 4000) -> dict[str, np.ndarray]:
    d = rng.uniform(0.0, 10.0, n)
    truth = rng.uniform(0.0, 60.0, n)
    raw = truth + rng.normal(0.0, 1.0, n) * (1.0 + 0.4 * d if grows else 3.0)  # c = 0.4 is on the grid
    return {"symmetry_thigh_deg|raw": raw, "symmetry_thigh_deg|truth": truth, DIFFICULTY: d}


def test_a_residual_growing_with_the_difficulty_gets_a_scale_and_holds_in_hard_cases() -> None:
    rng = np.random.default_rng(0)
    fit, test = _cases(rng, True), _cases(rng, True)
    f = scaled_fit(fit["symmetry_thigh_deg|raw"], fit["symmetry_thigh_deg|truth"], fit[DIFFICULTY], False, 2, GRID)
    assert f["c"] > 0
    hard = test[DIFFICULTY] > 7.0
    inside, count, _ = score({"symmetry_thigh_deg": f}, test, {"symmetry_thigh_deg": test[DIFFICULTY]}, hard)
    assert 0.85 <= inside / count <= 0.95


def test_a_constant_residual_keeps_the_constant_width() -> None:
    rng = np.random.default_rng(1)
    fit = _cases(rng, False)
    f = scaled_fit(fit["symmetry_thigh_deg|raw"], fit["symmetry_thigh_deg|truth"], fit[DIFFICULTY], False, 2, GRID)
    assert f["c"] == 0.0


def test_foreshortening_is_the_steepest_bone_of_the_measure_out_of_the_image_plane() -> None:
    poses = np.zeros((2, SKELETON.num_joints, 3))
    hip, knee = SKELETON.index("left_hip"), SKELETON.index("left_knee")
    poses[0, knee] = poses[0, hip] + [0.1, 0.0, 0.0]  # in the image plane
    poses[1, knee] = poses[1, hip] + [0.0, 0.0, 0.1]  # along the camera axis
    uses = np.zeros(SKELETON.num_joints, bool)
    uses[[hip, knee]] = True
    assert np.allclose(foreshortening(poses, uses), [0.0, 1.0])
