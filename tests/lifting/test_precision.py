"""Which precision a lift's network runs in (`LiftConfig.bf16`, lifting/precision.py)."""

from __future__ import annotations

from dataclasses import replace

import pytest
import torch

from zedo_cli.errors import ConfigError
from zedo_cli.lifting import precision
from zedo_cli.lifting.config import get_preset
from zedo_cli.prior.model import Bfloat16Network
from zedo_cli.prior.weights import Prior


def test_presets_precision() -> None:
    assert get_preset("faithful").bf16 is False  # the reference's float32
    assert get_preset("fast").bf16 is None  # bfloat16 where the device has it
    assert get_preset("fast-bf16").bf16 is True
    assert get_preset("fast-fp32") == replace(get_preset("fast"), preset="fast-fp32", bf16=False)
    with pytest.raises(ConfigError, match="bf16"):
        replace(get_preset("fast"), bf16="yes")  # type: ignore[arg-type]


@pytest.mark.parametrize("native", [True, False])
def test_auto_follows_the_device(tiny_prior: Prior, monkeypatch: pytest.MonkeyPatch, native: bool) -> None:
    monkeypatch.setattr(precision, "native_bfloat16", lambda device: native)
    fast = get_preset("fast")
    assert precision.uses_bfloat16(fast, "cpu") is native
    net = precision.lift_network(tiny_prior.model, fast, "cpu")
    assert isinstance(net, Bfloat16Network) is native
    assert precision.lift_network(tiny_prior.model, replace(fast, bf16=False), "cpu") is tiny_prior.model
    assert isinstance(precision.lift_network(tiny_prior.model, replace(fast, bf16=True), "cpu"), Bfloat16Network)


def test_other_networks_run_under_autocast(tiny_prior: Prior) -> None:
    wrapped = torch.nn.Sequential()  # not a ScoreNet: an ensemble or a conditioned network
    wrapped.forward = lambda x, t: tiny_prior.model(x, t)  # type: ignore[method-assign]
    net = precision.lift_network(wrapped, replace(get_preset("fast"), bf16=True), "cpu")
    x = torch.randn(20, 12, 3) * 0.2
    with torch.no_grad():
        out = net(x, torch.tensor(0.1))
        full = tiny_prior.model(x, torch.tensor(0.1))
    assert out.dtype == torch.float32 and not torch.equal(out, full)
    assert (out - full).abs().mean() < 0.05 * full.abs().mean()


def test_a_result_records_the_precision_its_network_ran_in() -> None:
    from zedo_cli.pipeline.lift import network_precision

    native = "bfloat16" if precision.native_bfloat16("cpu") else "float32"
    assert network_precision(get_preset("fast"), "cpu") == native  # where the CPU has it
    assert network_precision(get_preset("fast-fp32"), "cpu") == "float32"
    assert network_precision(get_preset("faithful"), "cpu") == "float32"
    assert network_precision(get_preset("fast-bf16"), "cpu") == "bfloat16"
