"""Tests of denoising score matching training (zedo_cli.prior.training) and recipes (zedo_cli.prior.recipes),
with a tiny CPU prior on random poses."""

from __future__ import annotations

import json
from collections.abc import Iterator
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import torch

from zedo_cli.data.datasets import PoseSet
from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.errors import ConfigError
from zedo_cli.prior.model import PriorConfig, ScoreNet, parameter_count
from zedo_cli.prior.recipes import Recipe, fit_prior, load_recipe, with_overrides
from zedo_cli.prior.schedules import TrainConfig
from zedo_cli.prior.sde import SubVPSDE
from zedo_cli.prior.training import EMA, TrainProgress, TrainResult, dsm_loss, train_score_model

REPO = Path(__file__).resolve().parents[2]
SCRATCH_RECIPE = REPO / "weights_spec" / "syrip12-scratch.toml"
TINY = PriorConfig(num_joints=4, hidden=32, embed=16, groups=4, num_blocks=1)
FAST = TrainConfig(epochs=100, batch_size=64, lr=2e-3, warmup_steps=5, ema_decay=0.99, seed=0)


def _poses(n: int = 64, joints: int = 4, seed: int = 0) -> torch.Tensor:
    """Root-relative poses in metres: a fixed template plus small per-pose variation."""
    g = torch.Generator().manual_seed(seed)
    template = 0.15 * torch.randn(1, joints, 3, generator=g)
    poses = template + 0.02 * torch.randn(n, joints, 3, generator=g)
    return poses - poses.mean(dim=1, keepdim=True)


def _model(seed: int = 0, cfg: PriorConfig = TINY) -> ScoreNet:
    with torch.random.fork_rng():
        torch.manual_seed(seed)
        return ScoreNet(cfg)


def _train(model: ScoreNet | None = None, cfg: TrainConfig = FAST, **kwargs: object) -> TrainResult:
    return train_score_model(model or _model(), SubVPSDE(), _poses(), cfg, **kwargs)  # type: ignore[arg-type]


@pytest.fixture(scope="module", autouse=True)
def _one_thread() -> Iterator[None]:
    """Tiny models train ~50x slower with 2 intra-op threads on a busy 2-core machine."""
    threads = torch.get_num_threads()
    torch.set_num_threads(1)
    yield
    torch.set_num_threads(threads)


@pytest.fixture(scope="module")
def trained(_one_thread: None) -> tuple[ScoreNet, TrainResult]:
    model = _model()
    return model, _train(model)


def _states_equal(a: dict[str, torch.Tensor], b: dict[str, torch.Tensor]) -> bool:
    return a.keys() == b.keys() and all(torch.equal(a[k], b[k]) for k in a)


# --- training loop -------------------------------------------------------------------------


def test_training_lowers_the_loss(trained: tuple[ScoreNet, TrainResult]) -> None:
    _, result = trained
    history = result.loss_history
    assert len(history) == FAST.epochs
    assert all(np.isfinite(history))
    assert np.mean(history[-10:]) < 0.6 * np.mean(history[:10])
    assert result.final_loss == history[-1]
    assert result.steps == FAST.epochs  # 64 poses, batch 64: one step per epoch
    assert result.seconds > 0


def test_same_seed_gives_identical_weights_and_different_seeds_differ(
    trained: tuple[ScoreNet, TrainResult],
) -> None:
    _, first = trained
    again = _train()
    assert _states_equal(first.raw_state, again.raw_state)
    assert _states_equal(first.ema_state, again.ema_state)
    assert first.loss_history == again.loss_history
    other = _train(cfg=replace(FAST, seed=1))
    assert first.raw_state.keys() == other.raw_state.keys()
    assert not _states_equal(first.raw_state, other.raw_state)


def test_training_restores_the_global_rng_state() -> None:
    with torch.random.fork_rng():
        torch.manual_seed(1234)
        before = torch.get_rng_state()
        _train(cfg=replace(FAST, epochs=3))
        assert torch.equal(torch.get_rng_state(), before)


def test_frozen_parameters_are_not_changed() -> None:
    model = _model()
    for p in model.stem.parameters():
        p.requires_grad_(False)
    frozen = {n: p.detach().clone() for n, p in model.named_parameters() if n.startswith("stem.")}
    trainable_before = {n: p.detach().clone() for n, p in model.named_parameters() if not n.startswith("stem.")}
    result = _train(model, cfg=replace(FAST, epochs=10))
    for name, value in frozen.items():
        assert torch.equal(result.raw_state[name], value), name
        assert torch.equal(result.ema_state[name], value), name
    assert any(not torch.equal(result.raw_state[n], v) for n, v in trainable_before.items())


def test_ema_state_has_the_raw_keys_but_other_values(trained: tuple[ScoreNet, TrainResult]) -> None:
    model, result = trained
    assert result.ema_state.keys() == result.raw_state.keys() == model.state_dict().keys()
    assert not _states_equal(result.ema_state, result.raw_state)
    for key, raw in result.raw_state.items():
        assert result.ema_state[key].shape == raw.shape
        assert result.ema_state[key].dtype == raw.dtype
    # The model itself holds the raw weights and is left in eval mode.
    assert _states_equal(model.state_dict(), result.raw_state)
    assert not model.training


def test_callback_is_called_once_per_epoch() -> None:
    seen: list[TrainProgress] = []
    cfg = replace(FAST, epochs=7, batch_size=20)  # 64 poses: 4 steps per epoch
    result = _train(cfg=cfg, callback=seen.append)
    assert [p.epoch for p in seen] == list(range(1, 8))
    assert all(p.epochs == 7 for p in seen)
    assert [p.step for p in seen] == [4 * e for e in range(1, 8)]
    assert [p.loss for p in seen] == result.loss_history
    assert result.steps == 28


def test_progress_snapshots_are_the_weights_of_that_epoch() -> None:
    snapshots: dict[int, dict[str, dict[str, torch.Tensor]]] = {}

    def keep(progress: TrainProgress) -> None:
        assert progress.snapshot is not None
        snapshots[progress.epoch] = {w: progress.snapshot(w) for w in ("raw", "ema")}

    result = _train(cfg=replace(FAST, epochs=3, batch_size=20), callback=keep)
    assert _states_equal(snapshots[3]["raw"], result.raw_state)
    assert _states_equal(snapshots[3]["ema"], result.ema_state)
    assert not _states_equal(snapshots[1]["raw"], result.raw_state)  # copies, not live views
    assert not _states_equal(snapshots[1]["ema"], snapshots[1]["raw"])


@pytest.mark.parametrize(
    "kwargs",
    [
        {"epochs": 0},
        {"lr": 0.0},
        {"lr": -1e-4},
        {"lr": float("nan")},
        {"batch_size": 0},
        {"warmup_steps": -1},
    ],
)
def test_invalid_train_config_raises(kwargs: dict[str, float]) -> None:
    with pytest.raises(ConfigError):
        TrainConfig(**kwargs)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    "poses",
    [
        torch.zeros(8, 4, 2),
        torch.zeros(8, 12),
        torch.zeros(0, 4, 3),
        torch.tensor([[[0.0, 0.0, float("nan")]] * 4] * 8),
        torch.tensor([[[0.0, float("inf"), 0.0]] * 4] * 8),
    ],
)
def test_bad_poses_raise(poses: torch.Tensor) -> None:
    with pytest.raises(ConfigError):
        train_score_model(_model(), SubVPSDE(), poses, replace(FAST, epochs=1))


def test_dsm_loss_is_half_summed_squared_error() -> None:
    class Zero(torch.nn.Module):
        def forward(self, x: torch.Tensor, t: torch.Tensor) -> torch.Tensor:
            return torch.zeros_like(x)

    noise = torch.randn(5, 4, 3, generator=torch.Generator().manual_seed(3))
    loss = dsm_loss(Zero(), SubVPSDE(), _poses(5), torch.full((5,), 0.5), noise)
    expected = 0.5 * noise.pow(2).sum(dim=(1, 2)).mean()
    assert float(loss) == pytest.approx(float(expected), rel=1e-6)


def test_ema_warm_up_decay() -> None:
    p = torch.nn.Parameter(torch.zeros(3))
    ema = EMA([p], decay=0.9999)
    with torch.no_grad():
        p.fill_(1.0)
    ema.update()  # decay_1 = min(0.9999, 2/11)
    np.testing.assert_allclose(ema.shadow[0].numpy(), 1.0 - 2.0 / 11.0, rtol=1e-6)


# --- recipes -------------------------------------------------------------------------------


def test_load_scratch_recipe() -> None:
    recipe = load_recipe(SCRATCH_RECIPE)
    assert recipe.training.epochs == 8000
    assert recipe.training.batch_size == 5000
    assert recipe.training.lr == pytest.approx(2e-4)
    assert recipe.training.warmup_steps == 5000
    assert recipe.output.weights == "ema"  # chosen on held-out folds
    assert recipe.output.dtype == "float16"
    assert recipe.sde == SubVPSDE()
    cfg = recipe.prior_config(12)
    assert cfg == PriorConfig(num_joints=12)


def _write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "recipe.toml"
    path.write_text(text)
    return path


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ("[training]\nepochs = 10\nlearning_rate = 0.1\n", "learning_rate"),
        ("[model]\nwidth = 3\n", "width"),
        ("[model]\nnum_joints = 12\n", "num_joints"),
        ("[sde]\nbeta = 1.0\n", "beta"),
        ("[output]\nformat = 'x'\n", "format"),
        ("[optimizer]\nlr = 0.1\n", "optimizer"),
        ("[training]\nepochs = 0\n", "epochs"),
        ("[output]\nweights = 'best'\n", "best"),
        ("[training\n", "TOML"),
    ],
)
def test_bad_recipe_raises_naming_the_problem(tmp_path: Path, text: str, needle: str) -> None:
    path = _write(tmp_path, text)
    with pytest.raises(ConfigError) as info:
        load_recipe(path)
    assert needle in str(info.value)


def test_missing_recipe_file(tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match="absent.toml"):
        load_recipe(tmp_path / "absent.toml")


def test_partial_recipe_keeps_defaults(tmp_path: Path) -> None:
    recipe = load_recipe(_write(tmp_path, "[training]\nepochs = 12\n[data]\nnote = 'ignored'\n"))
    assert recipe.training == replace(TrainConfig(), epochs=12)
    assert recipe.model == {} and recipe.output.weights == "raw"


def test_with_overrides_replaces_only_given_values() -> None:
    recipe = load_recipe(SCRATCH_RECIPE)
    changed = with_overrides(recipe, epochs=3, lr=None, seed=7)
    assert changed.training == replace(recipe.training, epochs=3, seed=7)
    assert changed.model == recipe.model and changed.sde == recipe.sde and changed.output == recipe.output
    assert recipe.training.epochs == 8000  # the original is untouched
    assert with_overrides(recipe, epochs=None) == recipe
    with pytest.raises(ConfigError):
        with_overrides(recipe, epochs=0)


def test_fit_prior_tiny_is_seeded_and_keeps_rng() -> None:
    skel = get_skeleton("syrip12")
    data = PoseSet(_poses(16, joints=12).double().numpy(), skel, [str(i) for i in range(16)], "test")
    recipe = Recipe(
        model={"hidden": 32, "embed": 16, "groups": 4, "num_blocks": 1},
        training=TrainConfig(epochs=3, batch_size=16, warmup_steps=0, lr=1e-3),
    )
    with torch.random.fork_rng():
        torch.manual_seed(99)
        before = torch.get_rng_state()
        fit = fit_prior(data, recipe)
        assert torch.equal(torch.get_rng_state(), before)
    assert fit.config.num_joints == 12
    assert fit.parameters == parameter_count(_model(cfg=fit.config))
    again = fit_prior(data, recipe)
    assert _states_equal(fit.result.raw_state, again.result.raw_state)


def test_the_bundled_prior_is_what_its_recipe_writes() -> None:
    from safetensors import safe_open

    from zedo_cli.prior.weights import resolve_prior_path

    recipe = load_recipe(SCRATCH_RECIPE)
    with safe_open(str(resolve_prior_path("syrip12-scratch")), "pt") as f:
        training = json.loads(f.metadata()["training"])
    assert (training["weights"], training["dtype"]) == (recipe.output.weights, recipe.output.dtype)
    assert training["epochs"] == recipe.training.epochs and training["seed"] == recipe.training.seed
