"""What --seed does, exactly as docs/lifting.md states it ("Randomness and --seed"): lifting with one
hypothesis has no randomness, so its output does not depend on the seed (only params.seed records
it; several hypotheses: tests/cli/test_cli_uncertainty.py); the commands
that draw random numbers take every draw from their seed."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from helpers import synthetic_poses
from safetensors.torch import load_file
from test_cli import lift_args, runner, write_coco

from zedo_cli.cli import app
from zedo_cli.data.skeleton import get_skeleton


def test_lifting_does_not_depend_on_the_seed(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json")
    docs = []
    for seed in ("0", "12345"):
        result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "-o", "-", "--seed", seed))
        assert result.exit_code == 0, result.output
        docs.append(json.loads(result.stdout))
    assert docs[0]["params"]["seed"] == 0 and docs[1]["params"]["seed"] == 12345
    assert docs[0]["frames"] == docs[1]["frames"]


def test_training_is_reproducible_from_its_seed_and_changes_with_it(tmp_path: Path) -> None:
    npz = tmp_path / "poses.npz"
    np.savez(npz, poses=synthetic_poses(40, seed=5), joint_names=np.array(get_skeleton("syrip12").joints))

    def fit(seed: int, name: str) -> dict:
        out = tmp_path / name
        args = ["fit-prior", str(npz), "--epochs", "2", "--batch-size", "20", "--seed", str(seed), "-q",
                "--out", str(out), "--dtype", "float32"]  # fmt: skip
        result = runner.invoke(app, args)
        assert result.exit_code == 0, result.output
        return load_file(str(out))

    a, b, c = fit(3, "a.safetensors"), fit(3, "b.safetensors"), fit(4, "c.safetensors")
    assert all(np.array_equal(a[k].numpy(), b[k].numpy()) for k in a)
    assert any(not np.array_equal(a[k].numpy(), c[k].numpy()) for k in a if k.startswith("model."))
