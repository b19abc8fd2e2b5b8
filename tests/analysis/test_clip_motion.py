"""The benchmark clips' two motions between key poses (zedo_cli/evaluation/clips/eased.py, `interpolation`): the
`segments` motion keeps one infant's bones, which easing the joints' positions does not."""

from __future__ import annotations

import numpy as np
from helpers import synthetic_poses

from zedo_cli.evaluation.clips.eased import SYRIP12_JOINTS, make_sequences, segment_interpolation
from zedo_cli.evaluation.clips.eased import _segment_vectors as _segment_vectors


def _key_poses(count: int, seed: int) -> np.ndarray:
    poses = synthetic_poses(count, seed=seed)  # (P, 12, 3) syrip12, hip-centred
    return poses - (poses[:, [0]] + poses[:, [3]]) / 2  # the hips' midpoint at the origin


def test_segments_keep_the_first_key_poses_bones_and_pass_through_each_key_direction() -> None:
    keys = _key_poses(4, seed=3)
    ease = (1.0 - np.cos(np.pi * np.arange(30) / 30)) / 2
    seq = segment_interpolation(keys, ease, SYRIP12_JOINTS)  # (90, 12, 3)
    length = np.linalg.norm(_segment_vectors(seq, SYRIP12_JOINTS), axis=-1)  # (90, S)
    first = np.linalg.norm(_segment_vectors(keys[:1], SYRIP12_JOINTS), axis=-1)  # (1, S)
    np.testing.assert_allclose(length, np.repeat(first, len(seq), 0), rtol=1e-9)
    unit = _segment_vectors(keys, SYRIP12_JOINTS)
    unit /= np.linalg.norm(unit, axis=-1, keepdims=True)
    for i in range(3):  # frame 30 i is key pose i's directions, with the first key pose's lengths
        got = _segment_vectors(seq[30 * i : 30 * i + 1], SYRIP12_JOINTS)[0]
        np.testing.assert_allclose(got / np.linalg.norm(got, axis=-1, keepdims=True), unit[i], atol=1e-9)
    hips = (seq[:, SYRIP12_JOINTS.index("left_hip")] + seq[:, SYRIP12_JOINTS.index("right_hip")]) / 2
    np.testing.assert_allclose(hips, 0.0, atol=1e-12)


def test_positions_shorten_a_turning_bone_and_both_motions_draw_alike() -> None:
    keys = _key_poses(40, seed=5)
    settings = {"count": 2, "keyposes": 4, "transition_s": 1.0, "fps": 30.0, "noise_px": 0.0, "drop": 0.0, "gap": 3}
    a = make_sequences(keys, np.random.default_rng(1), **settings)
    b = make_sequences(keys, np.random.default_rng(1), **settings, interpolation="segments")
    la = np.linalg.norm(_segment_vectors(a["rel"], SYRIP12_JOINTS), axis=-1)  # (T, S)
    lb = np.linalg.norm(_segment_vectors(b["rel"], SYRIP12_JOINTS), axis=-1)
    assert (la.min(0) < 0.9 * la.max(0)).any()  # some bone shrinks half-way between key poses
    for track in (0, 1):
        at = b["tracks"] == track
        np.testing.assert_allclose(lb[at], np.repeat(lb[at][:1], at.sum(), 0), rtol=1e-9)
    np.testing.assert_array_equal(np.isnan(a["xy"]), np.isnan(b["xy"]))  # the same random draws
