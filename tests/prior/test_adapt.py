"""Adaptation: the controllable branch (zero-init identity, frozen base, strict loading),
fine-tuning, scratch, seeded subsets, and `zedo adapt` end to end on a tiny prior."""

from __future__ import annotations

import json

import numpy as np
import pytest
import torch
from helpers import write_coco
from safetensors import safe_open
from safetensors.torch import load_file, save_file
from typer.testing import CliRunner

from zedo_cli.cli import app
from zedo_cli.data.datasets import PoseSet
from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.errors import ConfigError, DataError, WeightsError
from zedo_cli.prior.adapt import adapt_prior, build_model, select_subset, write_adapted_prior
from zedo_cli.prior.control import ControlledScoreNet
from zedo_cli.prior.model import PriorConfig, ScoreNet
from zedo_cli.prior.schedules import ADAPT_TRAINING, SCRATCH_TRAINING, TrainConfig, default_training
from zedo_cli.prior.weights import load_prior

runner = CliRunner()
TINY = TrainConfig(epochs=3, batch_size=8, warmup_steps=0, lr=1e-3, seed=0)


def _infant_set(n: int = 12, seed: int = 0) -> PoseSet:
    rng = np.random.default_rng(seed)
    skel = get_skeleton("syrip12")
    poses = rng.normal(scale=0.08, size=(n, skel.num_joints, 3))
    poses -= poses[:, skel.root_indices].mean(axis=1, keepdims=True)
    return PoseSet(poses, skel, [f"p{i}" for i in range(n)], "test infants")


def _trained_base() -> ScoreNet:
    torch.manual_seed(3)
    net = ScoreNet(PriorConfig(num_joints=12, hidden=64, embed=32, groups=8)).eval()
    with torch.no_grad():  # non-trivial weights everywhere, biases included
        for p in net.parameters():
            p.add_(0.05 * torch.randn_like(p))
    return net


def test_control_starts_identical_to_its_base() -> None:
    base = _trained_base()
    controlled = ControlledScoreNet(base).eval()
    x, t = torch.randn(7, 12, 3), torch.rand(7)
    assert torch.equal(controlled(x, t), base(x, t))
    for name, p in controlled.named_parameters():
        if name.startswith("zero_"):
            assert not p.any(), f"{name} is not zero-initialised"


def test_control_copy_holds_the_loaded_base_weights() -> None:
    base = _trained_base()
    controlled = ControlledScoreNet(base)
    assert torch.equal(controlled.branch_stem.dense.weight, base.stem.dense.weight)
    assert torch.equal(controlled.branch_blocks[1].second.time_proj.bias, base.blocks[1].second.time_proj.bias)
    assert controlled.branch_stem.dense.weight.data_ptr() != base.stem.dense.weight.data_ptr()


def test_control_training_leaves_the_base_untouched_and_moves_the_branch(tiny_prior) -> None:
    before = {k: v.clone() for k, v in tiny_prior.model.state_dict().items()}
    adapted = adapt_prior(tiny_prior, _infant_set(), "control", TINY)
    model = adapted.model
    assert isinstance(model, ControlledScoreNet)
    for name, value in model.base.state_dict().items():
        assert torch.equal(value, before[name]), f"frozen base weight {name} changed"
    assert model.zero_stem.weight.abs().sum() > 0  # the connections learned something
    frozen = {n for n, p in model.named_parameters() if not p.requires_grad}
    assert frozen == {f"base.{n}" for n in before}  # time MLP and head included
    assert adapted.trainable + sum(v.numel() for v in before.values()) == adapted.total


def test_control_branch_changes_the_output_after_training(tiny_prior) -> None:
    adapted = adapt_prior(tiny_prior, _infant_set(), "control", TINY)
    x, t = torch.randn(4, 12, 3), torch.full((4,), 0.3)
    assert not torch.allclose(adapted.model.eval()(x, t), tiny_prior.model(x, t))


def test_finetune_trains_every_weight_and_scratch_starts_fresh(tiny_prior) -> None:
    ft = adapt_prior(tiny_prior, _infant_set(), "finetune", TINY)
    assert ft.trainable == ft.total
    assert not torch.equal(ft.model.head.weight, tiny_prior.model.head.weight)
    fresh = build_model(tiny_prior, "scratch", seed=0)
    assert not torch.equal(fresh.head.weight, tiny_prior.model.head.weight)
    assert torch.equal(fresh.head.weight, build_model(tiny_prior, "scratch", seed=0).head.weight)


def test_adaptation_does_not_modify_the_loaded_base(tiny_prior) -> None:
    before = {k: v.clone() for k, v in tiny_prior.model.state_dict().items()}
    adapt_prior(tiny_prior, _infant_set(), "finetune", TINY)
    for name, value in tiny_prior.model.state_dict().items():
        assert torch.equal(value, before[name])


def test_adapt_rejects_other_joint_sets_and_strategies(tiny_prior) -> None:
    data = _infant_set()
    skel17 = get_skeleton("h36m17")
    other = PoseSet(np.zeros((3, 17, 3)), skel17, ["a", "b", "c"], "adults")
    with pytest.raises(DataError, match="h36m17 joint set"):
        adapt_prior(tiny_prior, other, "finetune", TINY)
    with pytest.raises(ConfigError, match="unknown strategy"):
        adapt_prior(tiny_prior, data, "distill", TINY)


def test_subset_is_seeded_reproducible_and_bounded() -> None:
    data = _infant_set(50)
    a = select_subset(data, 20, seed=1)
    assert a.names == select_subset(data, 20, seed=1).names
    assert a.names != select_subset(data, 20, seed=2).names
    assert len(set(a.names)) == 20 and a.names == sorted(a.names, key=data.names.index)
    np.testing.assert_array_equal(a.poses, data.poses[[data.names.index(n) for n in a.names]])
    assert select_subset(data, None, seed=1) is data
    with pytest.raises(ConfigError, match="exceeds the 50"):
        select_subset(data, 51, seed=0)
    with pytest.raises(ConfigError, match="positive"):
        select_subset(data, 0, seed=0)


def test_controlled_prior_round_trips_and_names_its_base(tiny_prior, tmp_path) -> None:
    data = _infant_set()
    adapted = adapt_prior(tiny_prior, data, "control", TINY)
    path = tmp_path / "ca.safetensors"
    write_adapted_prior(
        path, adapted, tiny_prior, data, TINY, license_text="test terms", weights="raw", dtype=torch.float32
    )
    loaded = load_prior(path)
    assert isinstance(loaded.model, ControlledScoreNet)
    assert loaded.metadata["format_version"] == "2" and loaded.metadata["architecture"] == "control"
    assert loaded.metadata["adapted_from"]["sha256"] == tiny_prior.sha256
    assert loaded.metadata["training"]["strategy"] == "control"
    x, t = torch.randn(3, 12, 3), torch.full((3,), 0.2)
    torch.testing.assert_close(loaded.model(x, t), adapted.model.eval()(x, t))


def test_controlled_prior_loads_strictly(tiny_prior, tmp_path) -> None:
    data = _infant_set()
    adapted = adapt_prior(tiny_prior, data, "control", TINY)
    path = tmp_path / "ca.safetensors"
    write_adapted_prior(path, adapted, tiny_prior, data, TINY, license_text="t")
    with safe_open(str(path), framework="pt") as fh:
        meta = fh.metadata()
    tensors = load_file(str(path))
    missing = dict(tensors)
    del missing["model.zero_stem.weight"]
    save_file(missing, str(tmp_path / "missing.safetensors"), metadata=meta)
    with pytest.raises(WeightsError, match="do not match the model"):
        load_prior(tmp_path / "missing.safetensors")
    plain_meta = {**meta, "format_version": "1"}
    plain_meta.pop("architecture")
    save_file(tensors, str(tmp_path / "as_plain.safetensors"), metadata=plain_meta)
    with pytest.raises(WeightsError, match="do not match the model"):
        load_prior(tmp_path / "as_plain.safetensors")
    no_arch = {k: v for k, v in meta.items() if k != "architecture"}
    save_file(tensors, str(tmp_path / "no_arch.safetensors"), metadata=no_arch)
    with pytest.raises(WeightsError, match="architecture"):
        load_prior(tmp_path / "no_arch.safetensors")


def test_finetuned_prior_stays_format_version_1(tiny_prior, tmp_path) -> None:
    data = _infant_set()
    adapted = adapt_prior(tiny_prior, data, "finetune", TINY)
    path = tmp_path / "ft.safetensors"
    write_adapted_prior(path, adapted, tiny_prior, data, TINY, license_text="t")
    loaded = load_prior(path)
    assert loaded.metadata["format_version"] == "1" and isinstance(loaded.model, ScoreNet)
    assert loaded.metadata["adapted_from"]["file"] == tiny_prior.path.split("/")[-1]


def test_cli_adapt_then_lift_with_the_controlled_prior(tiny_prior, tmp_path) -> None:
    coco_file = write_coco(tmp_path / "kp.json")  # poses of the kind the tiny prior was trained on
    data = _infant_set(30)
    npz = tmp_path / "infants.npz"
    np.savez(npz, poses=data.poses, joint_names=np.array(data.skeleton.joints))
    out = tmp_path / "ca.safetensors"
    args = ["adapt", str(npz), "--base", tiny_prior.path, "--strategy", "control", "--limit", "10",
            "--epochs", "2", "--batch-size", "8", "--seed", "4", "--out", str(out), "-q"]  # fmt: skip
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    meta = load_prior(out).metadata
    assert meta["training"]["limit"] == 10 and meta["data"]["count"] == 10
    assert "seeded subset of 10 (seed 4)" in meta["data"]["source"]
    assert meta["training"]["epochs"] == 2 and meta["training"]["warmup_steps"] == ADAPT_TRAINING.warmup_steps
    again = runner.invoke(app, args)
    assert again.exit_code == 2 and "--overwrite" in again.output
    lifted = tmp_path / "lifted.json"
    result = runner.invoke(app, ["lift", str(coco_file), "--prior", str(out), "-o", str(lifted), "-q"])
    assert result.exit_code == 0, result.output
    assert json.loads(lifted.read_text())["frames"]


def test_scratch_keeps_the_core_recipe_and_adapting_strategies_the_short_one(tiny_prior, tmp_path) -> None:
    assert default_training("control") == default_training("finetune") == ADAPT_TRAINING
    assert default_training("scratch") == SCRATCH_TRAINING == TrainConfig()  # the core recipe
    with pytest.raises(ConfigError, match="unknown strategy"):
        default_training("nope")
    npz = tmp_path / "infants.npz"
    data = _infant_set(10)
    np.savez(npz, poses=data.poses, joint_names=np.array(data.skeleton.joints))
    out = tmp_path / "scratch.safetensors"
    args = ["adapt", str(npz), "--base", tiny_prior.path, "--strategy", "scratch", "--epochs", "2",
            "--out", str(out), "-q"]  # fmt: skip
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    assert load_prior(out).metadata["training"]["warmup_steps"] == SCRATCH_TRAINING.warmup_steps


def test_cli_adapt_usage_errors(tiny_prior, tmp_path) -> None:
    args = ["adapt", "--base", tiny_prior.path, "--strategy", "nope", "--out", str(tmp_path / "x")]
    result = runner.invoke(app, args)
    assert result.exit_code == 2 and "--strategy must be one of control, finetune, scratch" in result.output
    result = runner.invoke(app, ["adapt", "--base", tiny_prior.path, "--out", str(tmp_path / "x")])
    assert result.exit_code == 2 and "exactly one source" in result.output
    assert not (tmp_path / "x").exists()
