"""The precision of the prior's network in a lift (`LiftConfig.bf16`): float32, or bfloat16
(`prior.model.Bfloat16Network`) where that is asked for, or, with `bf16=None` (the `fast` preset),
where the device computes bfloat16 natively.

On a CPU with AMX the bfloat16 network step costs 0.4-0.5 times the float32 one and Test100 moves
by 0.01 mm (docs/benchmarks.md, "Where the time goes"); on a CPU without bfloat16 instructions torch
emulates bfloat16 and it is several times slower, so there `None` keeps float32. The ray geometry,
the bone-length terms and the rotation fit stay in float32 either way.
"""

from __future__ import annotations

from collections.abc import Callable

import torch

from ..prior.model import Bfloat16Network, ScoreNet
from .config import LiftConfig

Network = Callable[[torch.Tensor, torch.Tensor], torch.Tensor]  # eps (B, J, 3) of poses (B, J, 3) at a shared t


def native_bfloat16(device: str | torch.device) -> bool:
    """Whether `device` computes bfloat16 products natively: a CPU with AMX or AVX512-BF16, or a
    CUDA GPU that supports bfloat16."""
    kind = torch.device(device).type
    if kind == "cuda":
        return torch.cuda.is_bf16_supported()
    if kind == "cpu":
        return bool(torch.cpu._is_amx_tile_supported() or torch.cpu._is_avx512_bf16_supported())
    return False


def uses_bfloat16(cfg: LiftConfig, device: str | torch.device) -> bool:
    """Whether a lift with `cfg` on `device` runs its network's products in bfloat16."""
    return native_bfloat16(device) if cfg.bf16 is None else cfg.bf16


def lift_network(model: torch.nn.Module, cfg: LiftConfig, device: str | torch.device) -> Network:
    """The noise prediction a lift calls, float32 out: `model` itself in float32, or in bfloat16:
    a `ScoreNet` as `Bfloat16Network` (the weights cast once here, shared read-only by the lift's
    chunks), another network (an ensemble, a conditioned one) under torch's bfloat16 autocast."""
    if not uses_bfloat16(cfg, device):
        return model
    if isinstance(model, ScoreNet):
        return Bfloat16Network(model)
    kind = torch.device(device).type

    def autocast(x: torch.Tensor, t: torch.Tensor) -> torch.Tensor:
        with torch.autocast(device_type=kind, dtype=torch.bfloat16):
            return model(x, t).to(x.dtype)

    return autocast
