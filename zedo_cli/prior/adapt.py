"""Adapting a prior to a small infant data set: `control`, `finetune` or `scratch`.

- control: the base is frozen and a ControlNet-like branch (control.py) is trained; the written
  prior carries base and branch.
- finetune: every weight of a copy of the base is trained.
- scratch: a fresh network of the base's size is trained (the baseline the paper compares to).
All three use the same objective and training loop as `fit-prior` (training.py).
"""

from __future__ import annotations

import copy
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import torch
from torch import nn

from ..data.datasets import PoseSet
from ..errors import ConfigError, DataError
from .control import ControlledScoreNet
from .ensemble import EnsembleScoreNet
from .model import ScoreNet, parameter_count
from .schedules import ADAPT_TRAINING, STRATEGIES, TrainConfig
from .training import TrainProgress, TrainResult, train_score_model
from .weights import Prior, save_prior


def select_subset(data: PoseSet, limit: int | None, seed: int) -> PoseSet:
    """A seeded, reproducible subset of `limit` poses (all poses when `limit` is None).

    The same (data, limit, seed) always gives the same poses, in their original order.
    """
    if limit is None:
        return data
    if isinstance(limit, bool) or not isinstance(limit, int) or limit < 1:
        raise ConfigError(f"--limit must be a positive number of poses, got {limit!r}")
    if limit > len(data.names):
        raise ConfigError(f"--limit {limit} exceeds the {len(data.names)} training poses of {data.source}")
    rows = np.sort(np.random.default_rng(seed).choice(len(data.names), size=limit, replace=False))
    return PoseSet(
        data.poses[rows], data.skeleton, [data.names[i] for i in rows],
        f"{data.source}, seeded subset of {limit} (seed {seed})",
    )  # fmt: skip


def with_added_poses(data: PoseSet, extra: PoseSet) -> PoseSet:
    """`data` followed by `extra` (e.g. `zedo augment`'s converted poses), in one joint set."""
    if extra.skeleton.name != data.skeleton.name:
        raise DataError(
            f"{extra.source}: added poses are in the {extra.skeleton.name} joint set, the training poses "
            f"in {data.skeleton.name}"
        )
    return PoseSet(
        np.concatenate([data.poses, extra.poses]), data.skeleton, data.names + extra.names,
        f"{data.source} + {len(extra.names)} added poses ({extra.source})",
    )  # fmt: skip


def build_model(base: Prior, strategy: str, seed: int) -> nn.Module:
    """The network to train: a controlled copy, a full copy, or a fresh net of the base's size."""
    if strategy not in STRATEGIES:
        raise ConfigError(f"unknown strategy {strategy!r}; choose one of {', '.join(STRATEGIES)}")
    gen = torch.Generator().manual_seed(seed)
    if strategy == "control":
        # The copy is taken here, from the loaded base (not from random weights).
        return ControlledScoreNet(copy.deepcopy(base.model), prompt_generator=gen)
    if strategy == "finetune":
        model = copy.deepcopy(base.model)
        for p in model.parameters():
            p.requires_grad_(True)
        return model
    if not isinstance(base.model, ScoreNet):
        raise ConfigError("scratch needs a plain base prior for its size, not a controlled one")
    with torch.random.fork_rng():
        torch.manual_seed(seed)
        return ScoreNet(base.model.cfg)


@dataclass
class AdaptResult:
    model: nn.Module
    result: TrainResult
    strategy: str
    trainable: int
    total: int


def adapt_prior(
    base: Prior,
    data: PoseSet,
    strategy: str,
    cfg: TrainConfig = ADAPT_TRAINING,
    *,
    device: str = "cpu",
    callback: Callable[[TrainProgress], None] | None = None,
) -> AdaptResult:
    """Train `strategy`'s network on `data` (root-relative poses in the base's joint set)."""
    if data.skeleton.name != base.skeleton.name:
        raise DataError(
            f"{data.source}: poses are in the {data.skeleton.name} joint set but the base prior "
            f"is {base.skeleton.name}; adapt needs the same joint set"
        )
    if strategy == "control" and isinstance(base.model, ControlledScoreNet):
        raise ConfigError("the base prior already carries a control branch; control a plain prior")
    if isinstance(base.model, EnsembleScoreNet):
        raise ConfigError(f"{base.label} is an ensemble prior; adapt one plain prior (an ensemble's members are "
                          "trained separately: adapt each and combine them)")  # fmt: skip
    model = build_model(base, strategy, cfg.seed)
    poses = torch.as_tensor(data.poses, dtype=torch.float32)
    result = train_score_model(model, base.sde, poses, cfg, device=device, callback=callback)
    trainable = sum(p.numel() for p in model.parameters() if p.requires_grad)
    return AdaptResult(model.cpu(), result, strategy, trainable, parameter_count(model))


def in_memory_prior(adapted: AdaptResult, base: Prior, data: PoseSet, state: dict[str, torch.Tensor]) -> Prior:
    """The adapted network with weights `state` (e.g. `adapted.result.state("ema")` or a
    mid-training snapshot) as a Prior, without writing a file: for scoring candidates. Its
    template is the first adaptation pose, as in the written file."""
    adapted.model.load_state_dict(state)
    template = torch.as_tensor(data.poses[0], dtype=torch.float32)
    return Prior(adapted.model.eval(), base.sde, base.skeleton, template, {}, "", "adapted")


def write_adapted_prior(
    path: str | Path,
    adapted: AdaptResult,
    base: Prior,
    data: PoseSet,
    cfg: TrainConfig,
    *,
    license_text: str,
    weights: str = "ema",
    dtype: torch.dtype = torch.float16,
    extra: dict[str, Any] | None = None,
) -> str:
    """Write the adapted prior (loadable by `zedo lift` like any other); return its sha256.

    Its metadata names the base (file and sha256) and the strategy; the template is the first
    adaptation pose, as the reference does for infant priors.
    """
    state = adapted.result.state(weights)
    training = {
        **cfg.to_dict(),
        "strategy": adapted.strategy,
        "weights": weights,
        **adapted.result.summary(),
        "parameters": adapted.total,
        "trainable_parameters": adapted.trainable,
        **(extra or {}),
    }
    origin = None if adapted.strategy == "scratch" else {"file": Path(base.path).name, "sha256": base.sha256}
    return save_prior(
        path,
        state,
        base.model.cfg,
        base.sde,
        base.skeleton,
        torch.as_tensor(data.poses[0], dtype=torch.float32),
        training=training,
        data=data.summary(),
        license_text=license_text,
        dtype=dtype,
        architecture="control" if isinstance(adapted.model, ControlledScoreNet) else "scorenet",
        adapted_from=origin,
    )
