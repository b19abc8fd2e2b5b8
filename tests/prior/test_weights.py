"""Weights files: round trip, strict loading, and the bundled prior's contract."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import torch
from safetensors.torch import load_file, save_file

from zedo_cli.errors import WeightsError
from zedo_cli.prior.weights import (
    BUNDLED_PRIORS,
    DEFAULT_PRIOR,
    all_finite,
    bundled_prior_path,
    load_prior,
    resolve_prior_path,
)


def _rewrite(src: Path, dst: Path, *, meta: dict[str, str] | None = None, drop: str | None = None,
             add: str | None = None, nan: str | None = None) -> Path:  # fmt: skip
    from safetensors import safe_open

    with safe_open(str(src), framework="pt") as fh:
        metadata = dict(fh.metadata())
    tensors = load_file(str(src))
    metadata.update(meta or {})
    if drop:
        tensors.pop(drop)
    if add:
        tensors[add] = torch.zeros(2)
    if nan:
        tensors[nan] = tensors[nan].clone()
        tensors[nan].view(-1)[0] = float("nan")
    save_file(tensors, str(dst), metadata=metadata)
    return dst


def test_round_trip_keeps_metadata_and_weights(tiny_prior_path: Path) -> None:
    prior = load_prior(tiny_prior_path)
    assert prior.skeleton.name == "syrip12" and prior.template.shape == (12, 3)
    assert prior.metadata["model_config"]["hidden"] == 128
    assert prior.metadata["license"] == "test only" and len(prior.sha256) == 64
    assert not prior.model.training  # loaded in eval mode


def test_loading_for_another_skeleton_is_an_error(tiny_prior_path: Path) -> None:
    with pytest.raises(WeightsError, match="skeleton 'syrip12', not 'h36m17'"):
        load_prior(tiny_prior_path, skeleton="h36m17")


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"meta": {"format_version": "99"}}, "format_version '99' is not supported"),
        ({"meta": {"format": "other"}}, "metadata 'format'"),
        ({"meta": {"skeleton": "h36m17"}}, "joints"),
        ({"meta": {"model_config": "{not json"}}, "not valid JSON"),
        ({"meta": {"model_config": json.dumps({"num_joints": 12, "hidden": 128, "bogus": 1})}}, "unknown fields"),
        ({"drop": "model.head.bias"}, "do not match the model"),
        ({"drop": "template"}, "template"),
        ({"add": "surprise"}, "unexpected tensors"),
        # Every problem of the file is a WeightsError (exit 3), checked before allocating.
        ({"meta": {"skeleton": "nope"}}, "metadata 'skeleton': unknown skeleton 'nope'"),
        ({"meta": {"model_config": json.dumps({"num_joints": 12, "hidden": 0})}}, "model hidden must be a positive"),
        ({"meta": {"model_config": json.dumps({"num_joints": 12, "hidden": 128, "embed": 32, "groups": 8,
                                               "num_blocks": 1, "time_scale": float("nan")})}},
         "model_config.time_scale is nan"),
        ({"meta": {"sde_config": json.dumps({"type": "subvp", "beta_min": float("nan"), "beta_max": 20.0,
                                             "num_scales": 1000})}}, "beta_min"),
        ({"meta": {"sde_config": json.dumps({"type": "subvp", "beta_min": 0.1, "beta_max": 1e9, "num_scales": 1000})}},
         "beta_max"),
        ({"meta": {"sde_config": json.dumps({"type": "subvp", "beta_min": 0.1, "beta_max": 20.0, "num_scales": 0})}},
         "num_scales"),
        ({"meta": {"model_config": json.dumps([1, 2])}}, "must be a JSON object"),
        ({"nan": "model.head.weight"}, "'model.head.weight' holds NaN"),
        ({"nan": "template"}, "'template' holds NaN"),
    ],
)  # fmt: skip
def test_strict_loading_rejects_altered_files(
    tiny_prior_path: Path, tmp_path: Path, change: dict, message: str
) -> None:
    bad = _rewrite(tiny_prior_path, tmp_path / "bad.safetensors", **change)
    with pytest.raises(WeightsError, match=message):
        load_prior(bad)


@pytest.mark.parametrize("dtype", [torch.float16, torch.bfloat16, torch.float32])
def test_all_finite_finds_any_nan_or_infinity(dtype: torch.dtype) -> None:
    generator = torch.Generator().manual_seed(0)
    for size in (1, 7, 33, 4097, 100_003):  # sizes that end inside and outside a SIMD register
        clean = torch.randn(size, generator=generator).to(dtype)
        assert all_finite(clean) and all_finite(clean.reshape(1, -1))
        for value in (float("nan"), float("inf"), float("-inf")):
            for where in {0, size // 2, size - 1}:
                bad = clean.clone()
                bad[where] = value
                assert not all_finite(bad), (size, value, where)
    assert all_finite(torch.empty(0, dtype=dtype))


def test_the_loaded_weights_are_the_files(tiny_prior_path: Path) -> None:
    """The network is built on the meta device and given the file's tensors: every parameter is
    the file's value in float32, on the CPU, trainable as a built network's are."""
    prior = load_prior(tiny_prior_path)
    stored = load_file(str(tiny_prior_path))
    params = dict(prior.model.named_parameters())
    assert set(params) == {k.removeprefix("model.") for k in stored if k.startswith("model.")}
    for name, param in params.items():
        assert param.device.type == "cpu" and param.dtype == torch.float32 and param.requires_grad
        assert torch.equal(param.detach(), stored[f"model.{name}"].float())


def test_declared_sizes_are_checked_against_the_tensors_before_any_allocation(
    tiny_prior_path: Path, tmp_path: Path
) -> None:
    """A small file whose metadata declares a huge network (hidden 2**20: 4 TiB of float32 per
    layer) fails on the tensor shapes; the network is never built in memory."""
    config = {"num_joints": 12, "hidden": 2**20, "embed": 32, "groups": 8, "num_blocks": 1, "dropout": 0.0}
    bad = _rewrite(tiny_prior_path, tmp_path / "huge.safetensors", meta={"model_config": json.dumps(config)})
    with pytest.raises(WeightsError, match=r"model.stem.dense.weight has shape \[128, 36\], .* needs \[1048576, 36\]"):
        load_prior(bad)


def test_unreadable_or_missing_files_are_errors(tmp_path: Path) -> None:
    with pytest.raises(WeightsError, match="not found"):
        load_prior(tmp_path / "none.safetensors")
    junk = tmp_path / "junk.safetensors"
    junk.write_bytes(b"not a safetensors file")
    with pytest.raises(WeightsError, match="not a readable safetensors file"):
        load_prior(junk)


def test_resolve_prior_path() -> None:
    assert resolve_prior_path("some/file.safetensors") == Path("some/file.safetensors")
    with pytest.raises(WeightsError, match="unknown bundled prior"):
        bundled_prior_path("nope")


def test_bundled_default_prior_is_shipped_and_loads_strictly() -> None:
    path = bundled_prior_path(DEFAULT_PRIOR)
    assert path.name == BUNDLED_PRIORS[DEFAULT_PRIOR]
    prior = load_prior(path, skeleton="syrip12")
    assert prior.metadata["model_config"]["hidden"] == 1024  # the paper's size
    assert sum(p.numel() for p in prior.model.parameters()) == 7_172_644
    assert "non-commercial" in prior.metadata["license"]
    assert prior.metadata["data"]["count"] == 600
    assert all(v.dtype == torch.float16 for k, v in load_file(str(path)).items() if k.startswith("model."))
