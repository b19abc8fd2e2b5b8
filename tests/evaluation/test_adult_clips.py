"""Synthetic infant clips of real movement (zedo_cli.evaluation.clips): retargeting, resampling,
supine placement, projection, detector habits and determinism, on a generated adult file and, where
../shared/data is present, on the real adult and SyRIP files."""

from __future__ import annotations

import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from helpers import ADULT_DIR, SYRIP_DIR, synthetic_poses

from zedo_cli.data.datasets import syrip_rows_by_name, syrip_test_names
from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.errors import ConfigError
from zedo_cli.evaluation.clips import (
    ClipSettings,
    DetectorHabits,
    adult_infant_clips,
    apply_habits,
    infant_bodies_from_poses,
    infant_bodies_from_syrip,
    load_adult_library,
    retargeted_clips,
    segment_vectors,
)
from zedo_cli.evaluation.clips.infants import InfantBodies
from zedo_cli.evaluation.clips.motion import SEGMENTS, unit
from zedo_cli.evaluation.clips.source import AdultLibrary

H36M = get_skeleton("h36m17")
SYRIP12 = get_skeleton("syrip12")
EXACT = ClipSettings(habits=None)
needs_data = pytest.mark.skipif(not (ADULT_DIR.is_dir() and SYRIP_DIR.is_dir()), reason="../shared/data not found")


def _walker(t: np.ndarray, turn_rate: float) -> np.ndarray:
    """h36m17 poses `(T, 17, 3)` (+Y up, metres) of an adult walking along a circle: legs and arms
    swinging, knees bending, shoulders twisting, heading turning at `turn_rate` rad/s."""
    psi = turn_rate * t
    up = np.array([0.0, 1.0, 0.0])
    left = np.stack([np.cos(psi), 0 * psi, -np.sin(psi)], 1)
    fwd = np.cross(left, up)
    pelvis = np.stack([2 * np.sin(0.3 * t), 0.95 + 0.02 * np.sin(6 * t), 3 * t], 1)

    def limb(angle: np.ndarray) -> np.ndarray:
        return np.cos(angle)[:, None] * -up + np.sin(angle)[:, None] * fwd

    swing, bend = 0.5 * np.sin(2 * np.pi * t), 0.3 * (1 + np.sin(2 * np.pi * t + 1))
    twist = 0.2 * np.sin(2 * np.pi * t)
    sh_left = np.cos(twist)[:, None] * left + np.sin(twist)[:, None] * fwd
    at = {"pelvis": pelvis, "right_hip": pelvis - 0.1 * left, "left_hip": pelvis + 0.1 * left}
    for side, sign in (("left", 1.0), ("right", -1.0)):
        at[f"{side}_knee"] = at[f"{side}_hip"] + 0.42 * limb(sign * swing)
        at[f"{side}_ankle"] = at[f"{side}_knee"] + 0.4 * limb(sign * swing - bend)
    at["spine"], at["thorax"] = pelvis + 0.2 * up, pelvis + 0.45 * up
    at["neck"], at["head"] = pelvis + 0.55 * up, pelvis + 0.65 * up
    for side, sign in (("left", 1.0), ("right", -1.0)):
        at[f"{side}_shoulder"] = at["thorax"] + sign * 0.18 * sh_left
        at[f"{side}_elbow"] = at[f"{side}_shoulder"] + 0.28 * limb(-sign * swing + 0.3)
        at[f"{side}_wrist"] = at[f"{side}_elbow"] + 0.25 * limb(-sign * swing + 0.3 + bend)
    return np.stack([at[j] for j in H36M.joints], 1)


@pytest.fixture()
def adult_dir(tmp_path: Path) -> Path:
    """A fake adult file in the shared data's layout: a 6 s walk with a 0.8 s still gap, a 3 s walk
    and a 0.4 s clip (shorter than the default minimum), kept frames on 0.1 s steps, 10 fps."""
    walk = np.round(np.arange(0, 6.01, 0.1), 6)
    walk = walk[(walk < 2.0) | (walk > 2.75)]  # 2.0 -> 2.8: dropped frames, a still pose
    times = [walk, np.round(np.arange(0, 3.01, 0.1), 6), np.round(np.arange(0, 0.41, 0.1), 6)]
    poses = [_walker(times[0], 1.0), _walker(times[1] + 0.37, -0.6), _walker(times[2], 0.2)]
    names = ["walk_a", "walk_b", "short_c"]
    clip = np.concatenate([[n] * len(t) for n, t in zip(names, times, strict=True)])
    np.savez(tmp_path / "fake_h36m17.npz", poses=np.concatenate(poses).astype(np.float32), clip=clip,
             time=np.concatenate(times).astype(np.float32), fps=np.float32(10.0),
             frame=np.concatenate([np.round(t * 10).astype(np.int32) for t in times]),
             joint_names=np.array(H36M.joints))  # fmt: skip
    return tmp_path


@pytest.fixture()
def fake_library(adult_dir: Path) -> AdultLibrary:
    return load_adult_library(adult_dir, ("fake_h36m17.npz",))


@pytest.fixture(scope="module")
def infants() -> InfantBodies:
    return infant_bodies_from_poses(synthetic_poses(30, seed=5), [f"pose{i}" for i in range(30)], "generated")


def _adult_segments(adult_dir: Path, clip: str) -> tuple[np.ndarray, np.ndarray]:
    """The fake file's kept times and unit limb and trunk vectors of `clip`, by joint name."""
    with np.load(adult_dir / "fake_h36m17.npz") as d:
        rows = d["clip"] == clip
        poses, t = d["poses"][rows].astype(np.float64), d["time"][rows].astype(np.float64)
    at = {j: poses[:, H36M.index(j)] for j in H36M.joints}
    at["root"] = (at["left_hip"] + at["right_hip"]) / 2
    at["neck"] = (at["left_shoulder"] + at["right_shoulder"]) / 2
    return t, unit(np.stack([at[c] - at[p] for p, c in SEGMENTS], 1))


def test_bone_lengths_are_one_infants_and_directions_the_adults(fake_library, infants, adult_dir: Path) -> None:
    settings = replace(EXACT, symmetric_infant=False)
    clips = list(retargeted_clips(fake_library, infants, seed=3, settings=settings))
    assert [c.source_clips for c in clips] == [("walk_a",), ("walk_b",)]  # the 0.4 s clip is skipped
    for clip in clips:
        lengths = np.linalg.norm(segment_vectors(clip.poses3d), axis=-1)
        assert np.abs(lengths - clip.infant_lengths).max() < 1e-6
        drawn = infants.lengths[infants.names.index(clip.infant_source)]
        np.testing.assert_allclose(clip.infant_lengths, drawn, atol=1e-12)
        kept_t, adult = _adult_segments(adult_dir, clip.source_clips[0])
        frame = np.flatnonzero(np.abs(clip.source_time[:, None] - kept_t[None]).min(1) < 1e-6)
        sample = np.abs(clip.source_time[frame, None] - kept_t[None]).argmin(1)
        assert len(frame) >= len(kept_t) - 1
        expected = np.einsum("tij,tsj->tsi", clip.rotation[frame], adult[sample])
        got = unit(segment_vectors(clip.poses3d[frame]))
        assert np.abs(got - expected).max() < 1e-5


def test_symmetric_infant_has_equal_twin_limbs(fake_library, infants) -> None:
    clip = next(retargeted_clips(fake_library, infants, seed=0, settings=EXACT))
    lengths = np.linalg.norm(segment_vectors(clip.poses3d), axis=-1)[0]
    np.testing.assert_allclose(lengths[[5, 6, 9, 10]], lengths[[7, 8, 11, 12]], atol=1e-9)


def test_uniform_fps_and_still_gap_held(fake_library, infants) -> None:
    settings = replace(EXACT, fps=25.0)
    clip = next(retargeted_clips(fake_library, infants, seed=1, settings=settings))
    assert clip.fps == 25.0 and len(clip) == 6 * 25 + 1
    np.testing.assert_allclose(np.diff(clip.source_time), 1 / 25, atol=1e-6)
    dirs = unit(segment_vectors(clip.poses3d))
    body = np.einsum("tji,tsj->tsi", clip.rotation, dirs)  # back in the adult's world frame
    held = (clip.source_time >= 1.9 - 1e-6) & (clip.source_time <= 2.7 + 1e-6)  # 1.9 s: the last kept frame
    moving = (clip.source_time > 2.7 + 1e-6) & (clip.source_time < 2.8)
    assert np.abs(body[held] - body[held][:1]).max() < 1e-5
    assert np.abs(body[moving] - body[held][:1]).max() > 1e-3


def test_supine_head_up_and_heading_removed(fake_library, infants) -> None:
    for clip in adult_infant_clips(fake_library, infants, seconds=12.0, count=4, seed=2, settings=EXACT):
        at = {j: clip.poses3d[:, i] for i, j in enumerate(SYRIP12.joints)}
        hips, shoulders = (at["left_hip"] + at["right_hip"]) / 2, (at["left_shoulder"] + at["right_shoulder"]) / 2
        left = at["left_hip"] - at["right_hip"] + at["left_shoulder"] - at["right_shoulder"]
        normal = unit(np.cross(unit(left), unit(shoulders - hips)))  # the chest's forward
        assert normal[:, 2].mean() < -0.8  # towards the camera
        ixy = {j: clip.xy_exact[:, i] for i, j in enumerate(SYRIP12.joints)}
        head_up = (ixy["left_shoulder"] + ixy["right_shoulder"])[:, 1] < (ixy["left_hip"] + ixy["right_hip"])[:, 1]
        assert head_up.mean() > 0.95
        # the walker turns by up to 6 rad; laid down, its left axis only sways about image right
        assert unit(left)[:, 0].min() > 0.5
        assert np.ptp(hips, axis=0).max() < 0.1  # no travel: the pelvis drifts by centimetres


def test_projection_matches_intrinsics(fake_library, infants) -> None:
    clip = next(adult_infant_clips(fake_library, infants, seconds=5.0, count=1, seed=4, settings=EXACT))
    k = clip.intrinsics.matrix()
    p = clip.poses3d
    manual = np.stack([k[0, 0] * p[..., 0] / p[..., 2] + k[0, 2], k[1, 1] * p[..., 1] / p[..., 2] + k[1, 2]], -1)
    np.testing.assert_allclose(clip.xy_exact, manual, atol=1e-9)
    np.testing.assert_array_equal(clip.xy, clip.xy_exact)
    assert k[0, 2] == clip.image_size[0] / 2 and k[1, 2] == clip.image_size[1] / 2


def test_follow_on_clips_length_transitions_and_seed(fake_library, infants) -> None:
    settings = replace(EXACT, transition_s=0.4)
    clips = list(adult_infant_clips(fake_library, infants, seconds=20.0, count=3, seed=7, settings=settings))
    for clip in clips:
        assert len(clip) == 600 and len(clip.source_clips) >= 3  # 9.4 s of file: it wraps round
        transition = clip.source_segment < 0
        assert np.isnan(clip.source_time[transition]).all() and np.isfinite(clip.source_time[~transition]).all()
        edges = np.flatnonzero(np.diff(np.r_[0, transition.astype(int), 0]))
        starts, ends = edges[0::2], edges[1::2]
        inner = (starts > 0) & (ends < len(clip))  # runs the crop did not cut
        assert inner.any() and set((ends - starts)[inner].tolist()) == {12}  # 0.4 s at 30 fps between clips
        lengths = np.linalg.norm(segment_vectors(clip.poses3d), axis=-1)
        assert np.abs(lengths - clip.infant_lengths).max() < 1e-6  # one infant through the joins
    again = list(adult_infant_clips(fake_library, infants, seconds=20.0, count=3, seed=7, settings=settings))
    other = list(adult_infant_clips(fake_library, infants, seconds=20.0, count=3, seed=8, settings=settings))
    for a, b, c in zip(clips, again, other, strict=True):
        for name in ("poses3d", "xy", "confidence", "source_time"):
            np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
        assert a.infant_source == b.infant_source and a.camera == b.camera
        assert not np.array_equal(a.poses3d, c.poses3d)


def test_habits_seeded_with_defaults(fake_library, infants) -> None:
    a = next(adult_infant_clips(fake_library, infants, seconds=10.0, count=1, seed=5))
    b = next(adult_infant_clips(fake_library, infants, seconds=10.0, count=1, seed=5))
    np.testing.assert_array_equal(a.xy, b.xy)
    np.testing.assert_array_equal(a.masks.dropped, b.masks.dropped)
    assert np.isnan(a.xy).any() and (a.confidence[np.isnan(a.xy).any(-1)] == 0).all()


def test_habit_masks_say_what_was_injected() -> None:
    rng = np.random.default_rng(0)
    exact = 300 + 50 * rng.normal(size=(3000, 12, 2))
    habits = DetectorHabits(jitter_px=0.0, dropout=0.05, swaps_per_min=20, hand_jumps_per_min=20, losses_per_min=5)
    xy, conf, m = apply_habits(exact, 30.0, habits, np.random.default_rng(1))
    assert m.swapped.any() and m.hand_jump.any() and m.dropped.any() and m.lost.any()
    missing = np.isnan(xy).any(-1)
    np.testing.assert_array_equal(missing, m.dropped | m.lost[:, None])
    assert (conf[missing] == 0).all() and (conf[~missing] >= 0.5).all()
    assert not (m.lost[:, None] & (m.dropped | m.hand_jump)).any() and not (m.lost & m.swapped).any()
    flipped = exact[:, SYRIP12.flip_permutation]
    expected = np.where(m.swapped[:, None, None], flipped, exact)
    clean = ~missing & ~m.hand_jump
    np.testing.assert_array_equal(xy[clean], expected[clean])
    assert set(np.flatnonzero(m.hand_jump.any(0)).tolist()) <= {
        SYRIP12.index("left_wrist"),
        SYRIP12.index("right_wrist"),
    }
    moved = np.linalg.norm(xy - expected, axis=-1)[m.hand_jump]
    assert moved.min() > 1.0  # the wrist went to the adult's hand
    with pytest.raises(ConfigError):
        DetectorHabits(dropout=1.5)


def test_settings_refused(fake_library, infants) -> None:
    with pytest.raises(ConfigError):
        ClipSettings(fps=0.0)
    with pytest.raises(ConfigError):
        adult_infant_clips(fake_library, infants, seconds=700.0, count=1, seed=0)  # over 10 minutes, at the call


@needs_data
def test_infants_are_syrip_training_poses_only() -> None:
    bodies = infant_bodies_from_syrip(SYRIP_DIR)
    rows = syrip_rows_by_name(SYRIP_DIR)
    test = set(syrip_test_names(SYRIP_DIR))
    assert len(bodies.names) == 600 and not test & set(bodies.names)
    used = np.array([rows[n] for n in bodies.names])
    assert not ((used >= 300) & (used <= 1299)).any()  # the reserved synthetic rows
    raw = np.load(SYRIP_DIR / "poses3d_corrected.npy")
    lsp = get_skeleton("lsp14")
    thigh = np.linalg.norm(raw[used, lsp.index("left_knee")] - raw[used, lsp.index("left_hip")], axis=-1)
    np.testing.assert_allclose(bodies.lengths[:, 5], thigh, atol=1e-12)


@needs_data
def test_real_files_fast_supine_one_infant() -> None:
    library = load_adult_library(ADULT_DIR)
    bodies = infant_bodies_from_syrip(SYRIP_DIR)
    assert {c.file for c in library.clips} == {"bandai_namco_h36m17.npz", "cmu_dmgnn_h36m17.npz",
                                               "deepmimic_pybullet_h36m17.npz"}  # fmt: skip
    start = time.perf_counter()
    clips = list(adult_infant_clips(library, bodies, seconds=10.0, count=20, seed=0))
    assert time.perf_counter() - start < 3.0
    for clip in clips:
        assert clip.poses3d.shape == (300, 12, 3) and clip.infant_source in bodies.names
        lengths = np.linalg.norm(segment_vectors(clip.poses3d), axis=-1)
        assert np.abs(lengths - clip.infant_lengths).max() < 1e-6
        xy = clip.xy_exact
        shoulders_y, hips_y = xy[:, [6, 9], 1].mean(1), xy[:, [0, 3], 1].mean(1)
        assert (shoulders_y < hips_y).mean() > 0.9
        assert 0.4 < np.median(clip.poses3d[:, [0, 3], 2]) < 2.0


def test_turned_supine_faces_the_camera_head_up_and_keeps_the_shape() -> None:
    from zedo_cli.evaluation.clips.cameras import turned_supine
    from zedo_cli.evaluation.clips.stillness import trunk_axes

    poses = synthetic_poses(6, seed=3)
    q, r = np.linalg.qr(np.random.default_rng(4).normal(size=(6, 3, 3)))
    q = q * np.sign(np.diagonal(r, axis1=1, axis2=2))[:, None]
    rotations = q * np.sign(np.linalg.det(q))[:, None, None]  # proper rotations, no mirror
    tumbled = np.einsum("pij,pmj->pmi", rotations, poses)
    turned = turned_supine(tumbled, SYRIP12.joints)
    axes, _ = trunk_axes(turned, SYRIP12.joints)  # rows: left, up, forward
    np.testing.assert_allclose(axes, np.broadcast_to(np.diag([1.0, -1.0, -1.0]), axes.shape), atol=1e-9)
    # a rotation about each pose's own origin: distances between joints kept
    gaps = lambda p: np.linalg.norm(p[:, :, None] - p[:, None], axis=-1)  # noqa: E731
    np.testing.assert_allclose(gaps(turned), gaps(poses), atol=1e-12)
    np.testing.assert_allclose(turned_supine(turned, SYRIP12.joints), turned, atol=1e-12)
