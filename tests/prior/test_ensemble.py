"""Ensemble priors: the mean of the members' predictions, the file round trip, combining, training."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import torch
from helpers import SKELETON, synthetic_poses
from safetensors.torch import load_file, save_file
from typer.testing import CliRunner

from zedo_cli.cli import app
from zedo_cli.errors import ConfigError, WeightsError
from zedo_cli.prior.adapt import adapt_prior
from zedo_cli.prior.combine import combine_priors
from zedo_cli.prior.ensemble import EnsembleScoreNet, ensemble_state
from zedo_cli.prior.model import PriorConfig, ScoreNet
from zedo_cli.prior.sde import SubVPSDE
from zedo_cli.prior.weights import load_prior, save_prior

runner = CliRunner()
CFG = PriorConfig(12, hidden=32, embed=8, groups=4, num_blocks=1, dropout=0.0)


def _member(seed: int, cfg: PriorConfig = CFG) -> ScoreNet:
    with torch.random.fork_rng():
        torch.manual_seed(seed)
        return ScoreNet(cfg).eval()


def _save(path: Path, model: ScoreNet, *, template: torch.Tensor | None = None, data: str = "synthetic") -> Path:
    template = torch.zeros(12, 3) if template is None else template
    save_prior(path, model.state_dict(), model.cfg, SubVPSDE(), SKELETON, template, training={"seed": 0},
               data={"source": data}, license_text="test only", dtype=torch.float32)  # fmt: skip
    return path


def test_the_ensemble_predicts_the_mean_of_its_members() -> None:
    members = [_member(1), _member(2), _member(3)]
    x, t = torch.randn(5, 12, 3), torch.tensor(0.05)
    expected = torch.stack([m(x, t) for m in members]).mean(0)
    assert torch.allclose(EnsembleScoreNet(members)(x, t), expected, atol=1e-6)


def test_an_ensemble_needs_two_members_of_one_config() -> None:
    with pytest.raises(ValueError, match="at least two"):
        EnsembleScoreNet([_member(1)])
    with pytest.raises(ValueError, match="one network config"):
        EnsembleScoreNet([_member(1), _member(2, PriorConfig(12, hidden=64, embed=8, groups=4, num_blocks=1))])


def test_ensemble_state_is_the_ensembles_state_dict() -> None:
    states = [_member(1).state_dict(), _member(2).state_dict()]
    ensemble = EnsembleScoreNet([_member(3), _member(4)])
    ensemble.load_state_dict(ensemble_state(states), strict=True)
    back = [m.state_dict() for m in ensemble.members]
    assert len(back) == 2 and all(torch.equal(back[i][k], states[i][k]) for i in range(2) for k in states[i])


def test_combined_file_loads_as_the_ensemble_of_its_members(tmp_path: Path) -> None:
    paths = [_save(tmp_path / f"m{i}.safetensors", _member(i)) for i in (1, 2)]
    out = tmp_path / "ens.safetensors"
    combine_priors(paths, out, dtype="float32")
    prior = load_prior(out)
    assert isinstance(prior.model, EnsembleScoreNet) and len(prior.model.members) == 2
    training = prior.metadata["training"]
    assert training["member_sha256"] == [load_prior(p).sha256 for p in paths]
    x, t = torch.randn(4, 12, 3), torch.tensor(0.1)
    with torch.no_grad():
        expected = (load_prior(paths[0]).model(x, t) + load_prior(paths[1]).model(x, t)) / 2
        assert torch.allclose(prior.model(x, t), expected, atol=1e-6)


def test_float16_members_keep_their_exact_weights(tmp_path: Path) -> None:
    paths = []
    for i in (1, 2):
        model = _member(i)
        path = tmp_path / f"h{i}.safetensors"
        save_prior(path, model.state_dict(), CFG, SubVPSDE(), SKELETON, torch.zeros(12, 3), training={},
                   data={"source": "synthetic"}, license_text="test only", dtype=torch.float16)  # fmt: skip
        paths.append(path)
    combine_priors(paths, tmp_path / "ens.safetensors")
    tensors = load_file(str(tmp_path / "ens.safetensors"))
    for i, path in enumerate(paths):
        for name, value in load_file(str(path)).items():
            if name.startswith("model."):
                assert torch.equal(tensors[f"model.members.{i}.{name[len('model.') :]}"], value)


@pytest.mark.parametrize(
    ("second", "needle"),
    [
        (lambda d: _save(d / "b.safetensors", _member(2, PriorConfig(12, hidden=64, embed=8, groups=4, num_blocks=1))),
         "model_config differs"),
        (lambda d: _save(d / "b.safetensors", _member(2), data="other poses"), "data differs"),
        (lambda d: _save(d / "b.safetensors", _member(2), template=torch.ones(12, 3)), "template differs"),
    ],
)  # fmt: skip
def test_combining_priors_not_trained_alike_is_refused(tmp_path: Path, second, needle: str) -> None:
    first = _save(tmp_path / "a.safetensors", _member(1))
    with pytest.raises(WeightsError, match=needle):
        combine_priors([first, second(tmp_path)], tmp_path / "ens.safetensors")
    assert not (tmp_path / "ens.safetensors").exists()


def test_an_ensemble_is_not_combined_again(tmp_path: Path) -> None:
    paths = [_save(tmp_path / f"m{i}.safetensors", _member(i)) for i in (1, 2)]
    combine_priors(paths, tmp_path / "ens.safetensors")
    with pytest.raises(WeightsError, match="only plain priors"):
        combine_priors([paths[0], tmp_path / "ens.safetensors"], tmp_path / "again.safetensors")


@pytest.mark.parametrize(
    ("members", "needle"), [(None, "'members' is missing"), ("1", "from 2 to 16"), ("x", "from 2")]
)
def test_an_ensemble_file_with_a_bad_member_count_is_refused(tmp_path: Path, members: str | None, needle: str) -> None:
    paths = [_save(tmp_path / f"m{i}.safetensors", _member(i)) for i in (1, 2)]
    combine_priors(paths, tmp_path / "ens.safetensors")
    tensors = load_file(str(tmp_path / "ens.safetensors"))
    meta = dict(load_prior(tmp_path / "ens.safetensors").metadata)
    meta = {k: v if isinstance(v, str) else json.dumps(v) for k, v in meta.items()}
    meta.pop("members")
    if members is not None:
        meta["members"] = members
    save_file(tensors, str(tmp_path / "bad.safetensors"), metadata=meta)
    with pytest.raises(WeightsError, match=needle):
        load_prior(tmp_path / "bad.safetensors")


def test_adapting_an_ensemble_is_refused_with_advice(tmp_path: Path) -> None:
    from zedo_cli.data.datasets import PoseSet

    paths = [_save(tmp_path / f"m{i}.safetensors", _member(i)) for i in (1, 2)]
    combine_priors(paths, tmp_path / "ens.safetensors")
    poses = synthetic_poses(8, seed=1)
    data = PoseSet(poses, SKELETON, [str(i) for i in range(8)], "synthetic")
    with pytest.raises(ConfigError, match="ensemble prior; adapt one plain prior"):
        adapt_prior(load_prior(tmp_path / "ens.safetensors"), data, "finetune")


def test_fit_prior_with_an_ensemble_recipe_trains_one_member_per_seed(tmp_path: Path) -> None:
    from zedo_cli.data.skeleton import get_skeleton

    npz = tmp_path / "poses.npz"
    np.savez(npz, poses=synthetic_poses(40, seed=5), joint_names=np.array(get_skeleton("syrip12").joints))
    recipe = tmp_path / "r.toml"
    recipe.write_text("[model]\nhidden = 32\nembed = 8\ngroups = 4\nnum_blocks = 1\n[output]\nmembers = 2\n")
    args = ["fit-prior", str(npz), "--recipe", str(recipe), "--epochs", "2", "--batch-size", "20", "--seed", "3"]
    result = runner.invoke(app, [*args, "-q", "--out", str(tmp_path / "ens.safetensors")])
    assert result.exit_code == 0, result.output
    assert "an ensemble of 2" in result.output
    prior = load_prior(tmp_path / "ens.safetensors")
    assert isinstance(prior.model, EnsembleScoreNet)
    assert prior.metadata["training"]["seeds"] == [3, 4]
    # the members are the plain trainings of those seeds
    single = tmp_path / "r1.toml"
    single.write_text("[model]\nhidden = 32\nembed = 8\ngroups = 4\nnum_blocks = 1\n")
    args[3] = str(single)
    for i, seed in enumerate((3, 4)):
        args[-1] = str(seed)
        assert runner.invoke(app, [*args, "-q", "--out", str(tmp_path / f"s{seed}.safetensors")]).exit_code == 0
        plain = load_prior(tmp_path / f"s{seed}.safetensors").model.state_dict()
        member = prior.model.members[i].state_dict()
        assert all(torch.equal(plain[k], member[k]) for k in plain)


def test_a_bad_member_count_in_a_recipe_is_a_usage_error(tmp_path: Path) -> None:
    recipe = tmp_path / "r.toml"
    recipe.write_text("[output]\nmembers = 0\n")
    result = runner.invoke(
        app, ["fit-prior", "x.npz", "--recipe", str(recipe), "--out", str(tmp_path / "p.safetensors")]
    )
    assert result.exit_code == 2 and "output.members must be an integer from 1 to 16" in result.output
