"""Eased clips swaying about one place, as infants lie under a camera (`make_sequences(sway=...)`)."""

from __future__ import annotations

import numpy as np
from helpers import synthetic_poses

from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.evaluation.clips.cameras import Sway, turned_supine
from zedo_cli.evaluation.clips.eased import make_sequences
from zedo_cli.evaluation.clips.stillness import trunk_axes

JOINTS = get_skeleton("syrip12").joints


def _clip(sway: Sway | None) -> dict[str, np.ndarray]:
    poses = turned_supine(synthetic_poses(80, seed=5), JOINTS)
    return make_sequences(poses, np.random.default_rng(6), count=1, keyposes=61, transition_s=1.0, fps=10.0,
                          noise_px=0.0, drop=0.0, gap=0, sway=sway)  # fmt: skip


def test_a_long_swaying_clip_stays_in_place_and_chest_up() -> None:
    swaying, turning = _clip(Sway()), _clip(None)
    root = lambda c: (c["cam"] - c["rel"])[:, 0]  # noqa: E731
    assert np.ptp(root(swaying), axis=0).max() <= 2 * Sway().drift_m + 1e-9  # only the drift's sinusoids
    assert np.ptp(root(turning), axis=0).max() > 0.3  # constant drift: far from its start after 60 s
    forward = trunk_axes(swaying["rel"], JOINTS)[0][:, 2]
    facing = np.degrees(np.arccos(np.clip(-forward[:, 2], -1, 1)))
    assert facing.max() < 35  # the roll's sway, never turned away from the camera


def test_the_same_seed_gives_the_same_swaying_clip() -> None:
    a, b = _clip(Sway()), _clip(Sway())
    np.testing.assert_array_equal(a["xy"], b["xy"])
