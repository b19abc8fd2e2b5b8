"""Shared fixtures: a tiny syrip12 prior trained in seconds on generated poses."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
import torch
from helpers import SKELETON, synthetic_poses

from zedo_cli.prior.model import PriorConfig, ScoreNet
from zedo_cli.prior.schedules import TrainConfig
from zedo_cli.prior.sde import SubVPSDE
from zedo_cli.prior.training import train_score_model
from zedo_cli.prior.weights import Prior, load_prior, save_prior

if os.environ.get("PYTEST_XDIST_WORKER"):
    # The suite runs in two processes on two cores (pyproject's -n 2): one torch thread each, as two
    # threads each make OpenMP's workers wait on one another (the tiny prior took 59 s to train, not 4).
    torch.set_num_threads(1)


@pytest.fixture(scope="session")
def tiny_prior_path(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A small syrip12 prior (hidden 128) trained for a few seconds, saved as a weights file."""
    poses = synthetic_poses(512, seed=0)
    cfg = PriorConfig(12, hidden=128, embed=32, groups=8, num_blocks=1, dropout=0.0)
    with torch.random.fork_rng():
        torch.manual_seed(0)
        model = ScoreNet(cfg)
    train = TrainConfig(epochs=300, batch_size=256, lr=1e-3, warmup_steps=50, seed=0)
    result = train_score_model(model, SubVPSDE(), torch.tensor(poses, dtype=torch.float32), train)
    path = tmp_path_factory.mktemp("prior") / "tiny.safetensors"
    save_prior(path, result.raw_state, cfg, SubVPSDE(), SKELETON, torch.tensor(poses[0], dtype=torch.float32),
               training=train.to_dict(), data={"source": "synthetic"}, license_text="test only",
               dtype=torch.float32)  # fmt: skip
    return path


@pytest.fixture()
def tiny_prior(tiny_prior_path: Path) -> Prior:
    return load_prior(tiny_prior_path)
