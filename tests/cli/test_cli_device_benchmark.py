"""`zedo benchmark --scale` from the command line, on the CPU with a tiny prior: the
JSON report and the refusals (one line, exit 2) before any work."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import torch
from helpers import tiny_recipe
from test_cli import runner

from zedo_cli.cli import app
from zedo_cli.evaluation.device_benchmark import CLASSES

TINY_RECIPE = tiny_recipe(epochs=8000, batch_size=5000)


def test_scale_option_prints_json(tiny_prior_path: Path, tmp_path: Path) -> None:
    (tmp_path / "r.toml").write_text(TINY_RECIPE)
    args = ["benchmark", "--scale", "64", "--prior", str(tiny_prior_path), "--agreement-poses", "64", "--fit-epochs",
            "2", "--fit-recipe", str(tmp_path / "r.toml"), "--chunk-size", "32", "--json", "-q"]  # fmt: skip
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    assert doc["device"] == "cpu" and doc["preset"] == "fast" and doc["prior_sha256"]
    (run,) = doc["lift"]
    assert run["count"] == 64 and run["chunk_rows"] == 32 and run["poses_per_second"] > 0
    assert set(run) >= {"seconds", "lifted", "peak_memory_mib", "memory_kind"}
    assert doc["agreement"]["reference"] == "cpu" and doc["agreement"]["share_within_1mm"] == 1.0
    assert set(doc["agreement"]["counts"]) == set(CLASSES)
    assert doc["fit_prior"]["extrapolated"] is True and doc["fit_prior"]["recipe_epochs"] == 8000


@pytest.mark.skipif(torch.cuda.is_available(), reason="a GPU is present")
def test_scale_on_cuda_without_a_gpu_is_the_one_line_refusal(tiny_prior_path: Path) -> None:
    result = runner.invoke(app, ["benchmark", "--scale", "100000", "--device", "cuda", "--prior", str(tiny_prior_path)])
    assert result.exit_code == 2 and "no CUDA GPU" in result.output, result.output
    assert len(result.output.strip().splitlines()) == 1


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["--preset", "fast"], "--syrip-dir"),
        (["--scale", "0"], "--scale"),
        (["--scale", "10", "--agreement-poses", "-1"], "--agreement-poses"),
        (["--scale", "10", "--chunk-size", "0"], "--chunk-size"),
        (["--scale", "10", "--scale-preset", "nope"], "--scale-preset"),
        (["--scale", "10", "--fit-recipe", "missing.toml"], "--fit-recipe"),
    ],
)
def test_scale_options_are_checked_first(args: list[str], needle: str) -> None:
    result = runner.invoke(app, ["benchmark", *args])
    assert result.exit_code == 2, result.output
    assert result.output.startswith(f"zedo: error: {needle}") and len(result.output.strip().splitlines()) == 1
