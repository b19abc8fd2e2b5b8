"""Training recipes (TOML) and `fit_prior`: data -> trained score network -> weights file.

A recipe has the tables `[model]` (PriorConfig fields except num_joints), `[sde]`,
`[training]` (TrainConfig fields), `[augment]` (PoseAugmentation fields: per-batch random
rotation and scale, off by default) and `[output]` (`weights` = "raw" | "ema", `dtype` =
"float16" | "float32", `members` = the number of networks: 1, or an ensemble of that many trainings
with the seeds seed, seed + 1, ...). Unknown keys are errors. Command-line options override recipe values.
"""

from __future__ import annotations

import tomllib
from collections.abc import Callable
from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import Any

import torch

from ..data.adult import PoseAugmentation
from ..data.datasets import PoseSet
from ..errors import ConfigError
from .ensemble import ensemble_state
from .model import PriorConfig, ScoreNet, parameter_count
from .schedules import STORED_DTYPES, WEIGHT_CHOICES, TrainConfig
from .sde import SubVPSDE
from .training import TrainProgress, TrainResult, train_score_model
from .weights import MAX_MEMBERS, save_prior

SYRIP_LICENSE = (
    "Trained on SyRIP real-infant data (Huang, Fu, Liu, Ostadabbas, FG 2021) with the 3D "
    "corrections of Infant-Postural-Symmetry (Huang, Wan, Luan, Tunik, Ostadabbas, 2022). "
    "Their terms: 'This code is for non-commercial purpose only.' These weights are for "
    "research / non-commercial use only."
)
DTYPES = dict(zip(STORED_DTYPES, (torch.float16, torch.float32), strict=True))


@dataclass(frozen=True)
class OutputConfig:
    weights: str = "raw"  # the reference lifts with the raw (last-step) weights, not the EMA
    dtype: str = "float16"
    members: int = 1  # > 1: an ensemble (ensemble.py) of trainings with seeds seed, seed + 1, ...

    def __post_init__(self) -> None:
        if not isinstance(self.members, int) or isinstance(self.members, bool) or not 1 <= self.members <= MAX_MEMBERS:
            raise ConfigError(f"output.members must be an integer from 1 to {MAX_MEMBERS}, got {self.members!r}")
        if self.weights not in WEIGHT_CHOICES:
            raise ConfigError(f"output.weights must be one of {WEIGHT_CHOICES}, got {self.weights!r}")
        if self.dtype not in DTYPES:
            raise ConfigError(f"output.dtype must be one of {tuple(DTYPES)}, got {self.dtype!r}")


@dataclass(frozen=True)
class Recipe:
    model: dict[str, Any] = field(default_factory=dict)  # PriorConfig fields but num_joints
    sde: SubVPSDE = SubVPSDE()
    training: TrainConfig = TrainConfig()
    augment: PoseAugmentation = PoseAugmentation()
    output: OutputConfig = OutputConfig()

    def prior_config(self, num_joints: int) -> PriorConfig:
        return PriorConfig(num_joints=num_joints, **self.model)


def _checked(table: dict[str, Any], cls: type, where: str) -> dict[str, Any]:
    allowed = {f.name for f in fields(cls)} - {"num_joints"}
    unknown = set(table) - allowed
    if unknown:
        raise ConfigError(f"{where}: unknown keys {sorted(unknown)}; allowed: {sorted(allowed)}")
    return table


def load_recipe(path: str | Path) -> Recipe:
    path = Path(path)
    try:
        doc = tomllib.loads(path.read_text())
    except FileNotFoundError:
        raise ConfigError(f"{path}: recipe file not found") from None
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read the recipe ({exc.strerror})") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise ConfigError(f"{path}: not valid TOML ({exc})") from None
    known = {"model", "sde", "training", "augment", "output", "data"}  # [data] documents, CLI chooses
    unknown = set(doc) - known
    if unknown:
        raise ConfigError(f"{path}: unknown tables {sorted(unknown)}; allowed: {sorted(known)}")
    try:
        model = _checked(doc.get("model", {}), PriorConfig, f"{path} [model]")
        PriorConfig(num_joints=1, **model)  # validate the values now, not at training time
        return Recipe(
            model=model,
            sde=SubVPSDE(**_checked(doc.get("sde", {}), SubVPSDE, f"{path} [sde]")),
            training=TrainConfig(**_checked(doc.get("training", {}), TrainConfig, f"{path} [training]")),
            augment=PoseAugmentation(**_checked(doc.get("augment", {}), PoseAugmentation, f"{path} [augment]")),
            output=OutputConfig(**_checked(doc.get("output", {}), OutputConfig, f"{path} [output]")),
        )
    except TypeError as exc:
        raise ConfigError(f"{path}: {exc}") from None


def with_overrides(recipe: Recipe, **training: Any) -> Recipe:
    """The recipe with the given (non-None) training fields replaced."""
    changes = {k: v for k, v in training.items() if v is not None}
    return replace(recipe, training=replace(recipe.training, **changes)) if changes else recipe


def with_output(recipe: Recipe, *, weights: str | None = None, dtype: str | None = None) -> Recipe:
    """The recipe with the given (non-None) output choices replaced."""
    if weights is None and dtype is None:
        return recipe
    return replace(recipe, output=replace(recipe.output, weights=weights or recipe.output.weights,
                                          dtype=dtype or recipe.output.dtype))  # fmt: skip


@dataclass
class FitResult:
    result: TrainResult
    config: PriorConfig
    parameters: int


def fit_prior(
    data: PoseSet,
    recipe: Recipe,
    *,
    device: str = "cpu",
    callback: Callable[[TrainProgress], None] | None = None,
) -> FitResult:
    """Train a score network from scratch on `data` with `recipe`."""
    cfg = recipe.prior_config(data.skeleton.num_joints)
    with torch.random.fork_rng():
        torch.manual_seed(recipe.training.seed)  # initial weights; global RNG restored after
        model = ScoreNet(cfg)
    poses = torch.as_tensor(data.poses, dtype=torch.float32)
    augment = recipe.augment if recipe.augment.active else None
    result = train_score_model(
        model, recipe.sde, poses, recipe.training, device=device, callback=callback, augment=augment
    )
    return FitResult(result, cfg, parameter_count(model))


def member_seeds(recipe: Recipe) -> list[int]:
    """The training seeds of the recipe's networks: seed, seed + 1, ... (`output.members` of them)."""
    return [recipe.training.seed + i for i in range(recipe.output.members)]


def write_fitted_prior(
    path: str | Path,
    fit: FitResult | list[FitResult],
    data: PoseSet,
    recipe: Recipe,
    *,
    license_text: str,
    extra_training: dict[str, Any] | None = None,
) -> str:
    """Save the recipe's chosen weights (raw or EMA) with full metadata; return the sha256.
    A list of several fits (one per seed of `member_seeds`) is saved as one ensemble prior.

    The template is the first training pose, as in the reference.
    """
    fits = fit if isinstance(fit, list) else [fit]
    states = [f.result.state(recipe.output.weights) for f in fits]
    training = {
        **recipe.training.to_dict(),
        "weights": recipe.output.weights,
        "dtype": recipe.output.dtype,
        **fits[0].result.summary(),
        "parameters": fits[0].parameters,
        "augment": recipe.augment.to_dict(),
        **(extra_training or {}),
    }
    if len(fits) > 1:
        training["seeds"] = member_seeds(recipe)
        training["member_training"] = [f.result.summary() for f in fits]
    return save_prior(
        path,
        states[0] if len(states) == 1 else ensemble_state(states),
        fits[0].config,
        recipe.sde,
        data.skeleton,
        torch.as_tensor(data.poses[0], dtype=torch.float32),
        training=training,
        data=data.summary(),
        license_text=license_text,
        dtype=DTYPES[recipe.output.dtype],
        architecture="scorenet" if len(states) == 1 else "ensemble",
        members=len(states) if len(states) > 1 else None,
    )
