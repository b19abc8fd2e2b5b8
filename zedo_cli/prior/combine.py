"""Combine plain priors trained alike (same recipe and data, different seeds) into one ensemble file.

`zedo fit-prior` with a recipe's `output.members` > 1 trains the members one after another and
writes the ensemble itself; `combine_priors` does the same from member files trained apart
(on several machines, or a seed added to an existing prior):

    python -c "from zedo_cli.prior.combine import combine_priors; \\
        combine_priors(['seed0.safetensors', 'seed1.safetensors'], 'ensemble.safetensors')"
"""

from __future__ import annotations

from pathlib import Path

import torch

from ..errors import WeightsError
from .ensemble import ensemble_state
from .model import ScoreNet
from .recipes import DTYPES
from .weights import Prior, load_prior, save_prior


def combine_priors(paths: list[str | Path], out: str | Path, *, dtype: str = "float16") -> str:
    """Write the ensemble of the plain priors `paths` to `out`; return its sha256.

    The members must share skeleton, network config, SDE, template and training data (the
    first member's metadata is kept, with every member's training summary and sha256 added).
    float16 members stored again as float16 keep their exact weights.
    """
    if len(paths) < 2:
        raise WeightsError("combining needs at least two priors")
    members = [load_prior(p) for p in paths]
    first = members[0]
    for prior in members:
        _check_compatible(first, prior)
    states = [m.model.state_dict() for m in members]
    training = {
        **first.metadata["training"],
        "seeds": [m.metadata["training"].get("seed") for m in members],
        "member_training": [m.metadata["training"] for m in members],
        "member_sha256": [m.sha256 for m in members],
    }
    model: ScoreNet = first.model  # type: ignore[assignment]  # checked plain in _check_compatible
    return save_prior(
        out,
        ensemble_state(states),
        model.cfg,
        first.sde,
        first.skeleton,
        first.template,
        training=training,
        data=first.metadata["data"],
        license_text=first.metadata["license"],
        dtype=DTYPES[dtype],
        architecture="ensemble",
        members=len(members),
    )


def _check_compatible(first: Prior, other: Prior) -> None:
    if type(other.model) is not ScoreNet:
        raise WeightsError(f"{other.path}: only plain priors can be combined (not an adapted or ensemble one)")
    checks = {
        "skeleton": (first.skeleton.name, other.skeleton.name),
        "model_config": (first.metadata["model_config"], other.metadata["model_config"]),
        "sde_config": (first.metadata["sde_config"], other.metadata["sde_config"]),
        "data": (first.metadata["data"], other.metadata["data"]),
    }
    for field, (a, b) in checks.items():
        if a != b:
            raise WeightsError(
                f"{other.path}: metadata {field} differs from {first.path}'s; members must be trained alike"
            )
    if not torch.equal(first.template, other.template):
        raise WeightsError(f"{other.path}: template differs from {first.path}'s; members must share the training data")
