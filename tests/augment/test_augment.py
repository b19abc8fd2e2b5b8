"""`zedo augment`: the domain tokens, size handling, the SDEdit conversion, orientation matching,
the augmenter file, and `fit-augmenter` / `augment` / `adapt --add-poses` end to end."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import torch
from helpers import SKELETON, synthetic_poses
from typer.testing import CliRunner

from zedo_cli.augment.augmenter import build_augmenter_net, load_augmenter, save_augmenter, train_augmenter
from zedo_cli.augment.conversion import (
    SIZE_CLIP_SD,
    TORSO_JOINTS,
    SizeModel,
    choose_sources,
    convert_poses,
    domain_training_set,
    fit_size_model,
    limb_parents,
    orient_like,
    resize,
    skeleton_size,
    take_bone_lengths,
)
from zedo_cli.augment.domain_model import DomainScoreNet
from zedo_cli.cli import app
from zedo_cli.data.datasets import PoseSet
from zedo_cli.data.skeleton import Skeleton, bone_lengths, get_skeleton
from zedo_cli.errors import ConfigError, DataError, WeightsError
from zedo_cli.prior.model import PriorConfig, ScoreNet
from zedo_cli.prior.schedules import TrainConfig
from zedo_cli.prior.sde import SubVPSDE
from zedo_cli.prior.weights import load_prior
from zedo_cli.rotation import random_rotations

runner = CliRunner()
TINY_CFG = PriorConfig(12, hidden=64, embed=32, groups=8, num_blocks=1, dropout=0.0)
SIZES = SizeModel(canonical=3.0, infant_log_mean=float(np.log(1.0)), infant_log_std=0.05)


def _net(seed: int = 0) -> DomainScoreNet:
    torch.manual_seed(seed)
    return DomainScoreNet(ScoreNet(TINY_CFG), token_generator=torch.Generator().manual_seed(seed)).eval()


def _sets(n_adult: int = 40, n_infant: int = 10) -> tuple[PoseSet, PoseSet]:
    adult = synthetic_poses(n_adult, seed=1) * 3.0
    infant = synthetic_poses(n_infant, seed=2)
    return (
        PoseSet(adult, SKELETON, [f"a{i}" for i in range(n_adult)], "test adults"),
        PoseSet(infant, SKELETON, [f"i{i}" for i in range(n_infant)], "test infants"),
    )


def _convert(net: DomainScoreNet, poses: np.ndarray, **kwargs) -> np.ndarray:
    return convert_poses(net, SubVPSDE(), SIZES, SKELETON, poses, **{"strength": 0.5, "steps": 5, **kwargs})


def test_switching_the_domain_token_changes_the_output() -> None:
    net = _net()
    x = torch.tensor(synthetic_poses(4, seed=0), dtype=torch.float32)
    t = torch.full((4,), 0.3)
    adult, infant = net(x, t, 0), net(x, t, 1)
    assert not torch.allclose(adult, infant)
    mixed = net(x, t, torch.tensor([0, 1, 0, 1]))
    torch.testing.assert_close(mixed[[0, 2]], adult[[0, 2]])
    torch.testing.assert_close(mixed[[1, 3]], infant[[1, 3]])
    poses = synthetic_poses(3, seed=5)
    assert not np.allclose(_convert(net, poses, domain="adult"), _convert(net, poses, domain="infant"))


def test_domain_model_without_token_difference_is_the_plain_network() -> None:
    net = _net()
    with torch.no_grad():
        net.tokens.zero_()
    x = torch.tensor(synthetic_poses(2, seed=0), dtype=torch.float32)
    t = torch.tensor(0.4)
    torch.testing.assert_close(net(x, t, 1), net.net(x, t))


def test_strength_zero_returns_the_input_and_infant_scale_only_resizes() -> None:
    poses = synthetic_poses(6, seed=3) * 3.0
    np.testing.assert_allclose(_convert(_net(), poses, strength=0.0, scale="keep"), poses, atol=1e-12)
    resized = _convert(_net(), poses, strength=0.0, scale="infant", seed=1)
    ratio = resized / poses
    np.testing.assert_allclose(ratio, ratio[:, :1, :1] * np.ones_like(ratio), rtol=1e-9)  # one factor per pose


def test_outputs_keep_joint_set_units_and_sizes() -> None:
    poses = synthetic_poses(8, seed=4) * 3.0
    kept = _convert(_net(), poses, scale="keep")
    assert kept.shape == poses.shape
    np.testing.assert_allclose(skeleton_size(kept, SKELETON), skeleton_size(poses, SKELETON), rtol=1e-9)
    infant = _convert(_net(), poses, scale="infant")
    sizes = skeleton_size(infant, SKELETON)
    bound = np.exp(SIZES.infant_log_std * SIZE_CLIP_SD) * (1 + 1e-9)
    assert np.all(sizes <= bound) and np.all(sizes >= 1 / bound)  # around the infant median (1 m here)
    np.testing.assert_allclose(infant[:, SKELETON.root_indices].mean(axis=1), 0.0, atol=1e-6)  # root-relative


def test_conversion_is_seeded() -> None:
    poses = synthetic_poses(5, seed=6)
    np.testing.assert_array_equal(_convert(_net(), poses, seed=3), _convert(_net(), poses, seed=3))
    assert not np.allclose(_convert(_net(), poses, seed=3), _convert(_net(), poses, seed=4))


def test_conversion_reports_every_reverse_step(monkeypatch) -> None:
    monkeypatch.setattr("zedo_cli.augment.conversion.CHUNK", 4)  # 10 poses: 3 chunks of reverse steps
    calls: list[tuple[int, int]] = []
    _convert(_net(), synthetic_poses(10, seed=8), steps=5, on_step=lambda done, total: calls.append((done, total)))
    assert calls == [(k, 15) for k in range(1, 16)]
    calls.clear()
    _convert(_net(), synthetic_poses(3, seed=8), strength=0.0, on_step=lambda done, total: calls.append((done, total)))
    assert calls == []  # strength 0: no diffusion, nothing to report


def test_higher_strength_moves_poses_further() -> None:
    poses = synthetic_poses(16, seed=7) * 3.0
    moved = [np.abs(_convert(_net(), poses, strength=s, scale="keep") - poses).mean() for s in (0.05, 0.5)]
    assert moved[0] < moved[1]


def test_conversion_rejects_bad_settings() -> None:
    poses = synthetic_poses(2, seed=0)
    with pytest.raises(ConfigError, match="strength"):
        _convert(_net(), poses, strength=1.5)
    with pytest.raises(ConfigError, match="steps"):
        _convert(_net(), poses, steps=0)
    with pytest.raises(ConfigError, match="scale"):
        _convert(_net(), poses, scale="adult")
    with pytest.raises(ConfigError, match="domain"):
        _convert(_net(), poses, domain="toddler")
    with pytest.raises(DataError, match="shape"):
        _convert(_net(), poses[:, :10])
    with pytest.raises(DataError, match="one point"):
        _convert(_net(), np.zeros((1, 12, 3)))


def test_sizes_and_balanced_training_set() -> None:
    adult, infant = _sets(40, 10)
    sizes = fit_size_model(adult, infant)
    assert sizes.canonical == pytest.approx(np.median(skeleton_size(adult.poses, SKELETON)))
    assert np.exp(sizes.infant_log_mean) == pytest.approx(np.exp(np.log(skeleton_size(infant.poses, SKELETON)).mean()))
    poses, labels = domain_training_set(adult, infant, sizes)
    assert (labels == 0).sum() == 40 and (labels == 1).sum() == 40  # infants repeated 4 times
    np.testing.assert_allclose(skeleton_size(poses.double().numpy(), SKELETON), sizes.canonical, rtol=1e-5)
    np.testing.assert_allclose(resize(infant.poses, SKELETON, 2.0)[0] / infant.poses[0], 2.0 / skeleton_size(
        infant.poses[:1], SKELETON)[0])  # fmt: skip


def test_orient_like_turns_the_torso_onto_a_reference() -> None:
    reference = synthetic_poses(1, seed=8)
    rot = random_rotations(5, torch.Generator().manual_seed(0)).numpy()
    turned = reference @ rot  # five orientations of the same pose
    oriented = orient_like(turned, reference, SKELETON, seed=0)
    np.testing.assert_allclose(oriented, np.repeat(reference, 5, axis=0), atol=1e-9)
    np.testing.assert_allclose(skeleton_size(oriented, SKELETON), skeleton_size(turned, SKELETON))


def _limb_directions(poses: np.ndarray) -> np.ndarray:
    pairs = limb_parents(SKELETON)
    vec = np.stack([poses[:, c] - poses[:, p] for p, c in pairs], axis=1)
    return vec / np.linalg.norm(vec, axis=-1, keepdims=True)


def test_take_bone_lengths_gives_reference_proportions_and_keeps_angles_and_size() -> None:
    poses = synthetic_poses(6, seed=3) * 3.0
    reference = synthetic_poses(1, seed=4)
    rebuilt = take_bone_lengths(poses, reference, SKELETON, seed=0)
    assert rebuilt.shape == poses.shape
    np.testing.assert_allclose(skeleton_size(rebuilt, SKELETON), skeleton_size(poses, SKELETON), rtol=1e-9)
    fractions = bone_lengths(rebuilt, SKELETON) / skeleton_size(rebuilt, SKELETON)[:, None]
    ref_fractions = bone_lengths(reference, SKELETON) / skeleton_size(reference, SKELETON)[:, None]
    np.testing.assert_allclose(fractions, np.repeat(ref_fractions, 6, axis=0), atol=1e-9)
    np.testing.assert_allclose(_limb_directions(rebuilt), _limb_directions(poses), atol=1e-9)
    np.testing.assert_allclose(rebuilt[:, SKELETON.root_indices].mean(axis=1), 0.0, atol=1e-12)
    # A pose with its own proportions comes back unchanged.
    np.testing.assert_allclose(
        take_bone_lengths(reference, reference, SKELETON),
        reference - reference[:, SKELETON.root_indices].mean(axis=1, keepdims=True),
        atol=1e-9,
    )
    np.testing.assert_array_equal(rebuilt, take_bone_lengths(poses, reference, SKELETON, seed=0))


def test_take_bone_lengths_needs_a_torso_and_connected_limbs() -> None:
    h36m = get_skeleton("h36m17")
    assert len(limb_parents(h36m)) == h36m.num_joints - 4  # every other joint hangs off the torso
    legs = Skeleton("legs", ("left_hip", "left_knee"), ((0, 1),), ("left_hip",))
    with pytest.raises(ConfigError, match="torso joints"):
        take_bone_lengths(np.zeros((1, 2, 3)), np.zeros((1, 2, 3)), legs)
    joints = (*TORSO_JOINTS, "left_knee")
    loose = Skeleton("loose", joints, ((0, 1), (2, 3)), ("left_hip", "right_hip"))
    with pytest.raises(ConfigError, match="not connected.*left_knee"):
        limb_parents(loose)


def test_choose_sources_is_seeded_and_repeats_only_when_needed() -> None:
    rows = choose_sources(100, 10, seed=0)
    assert len(set(rows)) == 10 and list(rows) == sorted(rows)
    np.testing.assert_array_equal(rows, choose_sources(100, 10, seed=0))
    assert len(choose_sources(3, 10, seed=0)) == 10
    with pytest.raises(ConfigError, match="count"):
        choose_sources(3, 0, seed=0)


def test_training_moves_tokens_and_file_round_trips(tiny_prior, tmp_path: Path) -> None:
    adult, infant = _sets()
    cfg = TrainConfig(epochs=2, batch_size=32, warmup_steps=0, lr=1e-3, seed=0)
    start = build_augmenter_net(tiny_prior, 12, seed=0).tokens.detach().clone()
    trained = train_augmenter(adult, infant, cfg, init=tiny_prior)
    assert not torch.allclose(trained.result.raw_state["tokens"], start)
    path = tmp_path / "aug.safetensors"
    save_augmenter(path, trained.result.raw_state, trained.model.cfg, trained.sde, SKELETON, trained.sizes,
                   training=cfg.to_dict(), data={}, license_text="test", dtype=torch.float32,
                   initialised_from={"file": "tiny.safetensors", "sha256": tiny_prior.sha256})  # fmt: skip
    loaded = load_augmenter(path)
    assert loaded.sizes == trained.sizes and loaded.metadata["initialised_from"]["sha256"] == tiny_prior.sha256
    x = torch.tensor(infant.poses[:3], dtype=torch.float32)
    trained.model.load_state_dict(trained.result.raw_state)
    torch.testing.assert_close(loaded.model(x, torch.tensor(0.2), 1), trained.model.eval()(x, torch.tensor(0.2), 1))


def test_augmenter_loading_is_strict(tiny_prior_path: Path, tmp_path: Path) -> None:
    with pytest.raises(WeightsError, match="that is a prior"):
        load_augmenter(tiny_prior_path)
    net = _net()
    path = tmp_path / "aug.safetensors"
    state = {k: v for k, v in net.state_dict().items() if k != "tokens"}
    save_augmenter(path, state, TINY_CFG, SubVPSDE(), SKELETON, SIZES, training={}, data={}, license_text="t")
    with pytest.raises(WeightsError, match="do not match"):
        load_augmenter(path)


def _write_npz(path: Path, poses: np.ndarray) -> Path:
    np.savez(path, poses=poses, joint_names=np.array(SKELETON.joints))
    return path


def test_cli_fit_augment_and_adapt_with_added_poses(tiny_prior_path: Path, tmp_path: Path) -> None:
    adult = _write_npz(tmp_path / "adult.npz", synthetic_poses(30, seed=1) * 3.0)
    infant = _write_npz(tmp_path / "infant.npz", synthetic_poses(10, seed=2))
    model = tmp_path / "aug.safetensors"
    fit = ["fit-augmenter", "--infant", str(infant), "--adult-poses", str(adult), "--init", str(tiny_prior_path),
           "--epochs", "1", "--batch-size", "32", "--out", str(model), "-q"]  # fmt: skip
    result = runner.invoke(app, fit)
    assert result.exit_code == 0, result.output
    out = tmp_path / "converted.npz"
    plots = tmp_path / "plots"
    convert = ["augment", str(adult), "--model", str(model), "--count", "12", "--steps", "3", "--orient", "infant",
               "--bones", "infant", "--infant", str(infant), "--plot", str(plots), "--out", str(out)]  # fmt: skip
    result = runner.invoke(app, convert)
    assert result.exit_code == 0, result.output
    with np.load(out) as data:
        assert data["poses"].shape == (12, 12, 3) and list(data["joint_names"]) == list(SKELETON.joints)
        assert data["source_poses"].shape == (12, 12, 3) and float(data["strength"]) == 0.2
        assert str(data["bones"]) == "infant"
        infant_fractions = (
            bone_lengths(synthetic_poses(10, seed=2), SKELETON)
            / skeleton_size(synthetic_poses(10, seed=2), SKELETON)[:, None]
        )
        fractions = bone_lengths(data["poses"], SKELETON) / skeleton_size(data["poses"], SKELETON)[:, None]
        assert all(np.abs(infant_fractions - f).max(axis=1).min() < 1e-9 for f in fractions)
    assert sorted(p.name for p in plots.iterdir()) == ["bone_angles.png", "bone_lengths.png", "pairs.png"]
    again = runner.invoke(app, convert)  # nothing replaced without --overwrite
    assert again.exit_code == 2 and "already exists" in again.output
    adapted = tmp_path / "ft.safetensors"
    result = runner.invoke(app, ["adapt", str(infant), "--add-poses", str(out), "--base", str(tiny_prior_path),
                                 "--strategy", "finetune", "--epochs", "1", "--out", str(adapted), "-q"])  # fmt: skip
    assert result.exit_code == 0, result.output
    assert "+ 12 added poses" in result.output or adapted.is_file()
    # The adapted prior carries the terms of the data behind the added poses.
    augmenter_terms = load_augmenter(model).metadata["license"]
    assert augmenter_terms and augmenter_terms in load_prior(adapted).metadata["license"]


def test_cli_augment_usage_errors(tiny_prior_path: Path, tmp_path: Path) -> None:
    adult = _write_npz(tmp_path / "adult.npz", synthetic_poses(5, seed=1))
    base = ["augment", str(adult), "--out", str(tmp_path / "o.npz")]
    result = runner.invoke(app, [*base, "--model", str(tiny_prior_path), "--strength", "1.5"])
    assert result.exit_code == 2 and "--strength" in result.output
    result = runner.invoke(app, [*base, "--model", str(tiny_prior_path)])
    assert result.exit_code == 3 and "that is a prior" in result.output
    result = runner.invoke(app, [*base, "--model", str(tiny_prior_path), "--orient", "infant"])
    assert result.exit_code == 2 and "infant reference" in result.output
    result = runner.invoke(app, [*base, "--model", str(tiny_prior_path), "--bones", "infant"])
    assert result.exit_code == 2 and "infant reference" in result.output
    result = runner.invoke(app, [*base, "--model", str(tiny_prior_path), "--bones", "adult"])
    assert result.exit_code == 2 and "--bones" in result.output
    result = runner.invoke(app, ["fit-augmenter", "--adult-poses", str(adult), "--out", str(tmp_path / "a.st")])
    assert result.exit_code == 2 and "infant poses" in result.output
    assert not (tmp_path / "o.npz").exists()
