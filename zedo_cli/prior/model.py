"""The score network: an MLP over a flattened pose plus a positional time embedding.

ALGORITHM.md section 2.1 (the reference's `ScoreModelFC_Adv` with two residual blocks). The
network predicts the noise eps; it knows nothing of the SDE, data sets or camera.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import torch
from torch import nn


@dataclass(frozen=True)
class PriorConfig:
    """Score network size. Defaults are the paper's (hidden 1024, embed 512, 2 blocks)."""

    num_joints: int
    hidden: int = 1024
    embed: int = 512
    num_blocks: int = 2
    groups: int = 32
    dropout: float = 0.25  # the reference hard-codes 0.25 (its config's 0.1 is ignored)
    time_scale: float = 999.0  # the network sees 999 * t

    def __post_init__(self) -> None:
        from ..errors import ConfigError

        for name in ("num_joints", "hidden", "embed", "num_blocks", "groups"):
            value = getattr(self, name)
            if not isinstance(value, int) or isinstance(value, bool) or value < 1:
                raise ConfigError(f"model {name} must be a positive integer, got {value!r}")
        if self.hidden % self.groups:
            raise ConfigError(f"model hidden ({self.hidden}) must be divisible by groups ({self.groups})")
        if self.embed % 2 or self.embed < 4:
            raise ConfigError(f"model embed must be an even number >= 4, got {self.embed}")
        if not isinstance(self.dropout, (int, float)) or not 0 <= self.dropout < 1:
            raise ConfigError(f"model dropout must be in [0, 1), got {self.dropout!r}")
        if not isinstance(self.time_scale, (int, float)) or not self.time_scale > 0:
            raise ConfigError(f"model time_scale must be > 0, got {self.time_scale!r}")

    def to_dict(self) -> dict[str, float | int]:
        return asdict(self)


def positional_embedding(labels: torch.Tensor, dim: int) -> torch.Tensor:
    """Sinusoidal features `(B, dim)` of `labels (B,)`: [sin(l w_k), cos(l w_k)], sin half first,
    with w_k = exp(-k ln(10000) / (dim/2 - 1))."""
    half = dim // 2
    freqs = torch.exp(-math.log(10000.0) * torch.arange(half, dtype=torch.float32, device=labels.device) / (half - 1))
    angles = labels.float()[:, None] * freqs[None, :]
    return torch.cat([torch.sin(angles), torch.cos(angles)], dim=1)


class DenseBlock(nn.Module):
    """Dropout(SiLU(GN(Linear(h) + Linear(temb)))): one dense layer with its own time projection."""

    def __init__(self, cfg: PriorConfig, in_features: int) -> None:
        super().__init__()
        self.dense = nn.Linear(in_features, cfg.hidden)
        self.time_proj = nn.Linear(cfg.embed, cfg.hidden)
        self.norm = nn.GroupNorm(cfg.groups, cfg.hidden)
        self.dropout = nn.Dropout(cfg.dropout)

    def pre_norm(self, h: torch.Tensor, temb: torch.Tensor) -> torch.Tensor:
        return self.dense(h) + self.time_proj(temb)

    def post_norm(self, pre: torch.Tensor) -> torch.Tensor:
        return self.dropout(nn.functional.silu(self.norm(pre)))

    def forward(self, h: torch.Tensor, temb: torch.Tensor) -> torch.Tensor:
        return self.post_norm(self.pre_norm(h, temb))


class ResidualBlock(nn.Module):
    """h + Dense2(Dense1(h)): two dense layers and one skip."""

    def __init__(self, cfg: PriorConfig) -> None:
        super().__init__()
        self.first = DenseBlock(cfg, cfg.hidden)
        self.second = DenseBlock(cfg, cfg.hidden)

    def forward(self, h: torch.Tensor, temb: torch.Tensor) -> torch.Tensor:
        return h + self.second(self.first(h, temb), temb)


class ScoreNet(nn.Module):
    """Noise-prediction network eps_theta(x, t) for poses `x (B, J, 3)` and times `t`.

    `t` is either `(B,)` or a scalar shared by the batch; a shared time computes the time
    path (embedding MLP and projections) once for the batch instead of once per pose.
    """

    def __init__(self, cfg: PriorConfig) -> None:
        super().__init__()
        self.cfg = cfg
        dim = 3 * cfg.num_joints
        self.time_mlp = nn.Sequential(nn.Linear(cfg.embed, cfg.embed), nn.SiLU())
        self.stem = DenseBlock(cfg, dim)
        self.blocks = nn.ModuleList(ResidualBlock(cfg) for _ in range(cfg.num_blocks))
        self.head = nn.Linear(cfg.hidden, dim)

    def time_embedding(self, t: torch.Tensor) -> torch.Tensor:
        labels = self.cfg.time_scale * t.reshape(-1)
        return self.time_mlp(positional_embedding(labels, self.cfg.embed))

    def forward(self, x: torch.Tensor, t: torch.Tensor) -> torch.Tensor:
        return self.denoise(x, self.time_embedding(t.to(x.dtype)))  # temb (B, E) or (1, E) when t is shared

    def denoise(self, x: torch.Tensor, temb: torch.Tensor) -> torch.Tensor:
        """The noise prediction given an already computed embedding (time, plus any condition)."""
        batch = x.shape[0]
        h = self.stem(x.reshape(batch, -1), temb)
        for block in self.blocks:
            h = block(h, temb)
        return self.head(h).reshape(x.shape)


def parameter_count(model: nn.Module) -> int:
    return sum(p.numel() for p in model.parameters())


def group_norm(h: torch.Tensor, groups: int, weight: torch.Tensor, bias: torch.Tensor, eps: float) -> torch.Tensor:
    """GroupNorm of features `h (B, C)` in `groups` groups with the affine `weight`, `bias (C,)`:
    each group's C / G features made a row of their own and normalised as one group (statistics in
    float32 whatever h's dtype), then the affine map. The same numbers to float rounding in a third
    of torch's GroupNorm time on (B, 1024) features in 32 groups (0.5-0.6 ms against 1.5-1.7 ms for
    512 rows on one thread, float32; a layer norm of the rows took 0.8-1.0 ms)."""
    flat = nn.functional.group_norm(h.reshape(-1, h.shape[1] // groups), 1, eps=eps)
    return torch.addcmul(bias, flat.reshape(h.shape), weight)


# Rows of every bfloat16 product. oneDNN picks its bfloat16 kernel (and so the order of each dot
# product's sums) by the number of rows: on an AMX CPU, products of 33-36, 37-704 and other row
# counts gave three different results for the same row. Products of exactly this many rows (the
# last block padded with zeros) give each row the same bits wherever it is, so a pose's lift does
# not depend on its chunk (lifting/chunks.py); 256 rows cost no more per row than 1024.
BF16_BLOCK_ROWS = 256


class Bfloat16Network:
    """`ScoreNet`'s noise prediction in bfloat16, for inference.

    The products, GroupNorm (as `group_norm`, its statistics in float32) and SiLU run in bfloat16;
    the time path, each layer's time projection (folded into its bias once per call: the time is
    shared by the batch), the residual sums and the output stay in float32. The weights are cast
    once. Products run in blocks of BF16_BLOCK_ROWS rows, so that a row's result does not depend
    on the batch. On a CPU with AMX a forward takes 0.3-0.4 times its float32 time, and its noise
    prediction is within 0.3 % of the float32 one (docs/benchmarks.md, "Where the time goes").
    """

    def __init__(self, net: ScoreNet) -> None:
        self.net = net
        half = torch.bfloat16
        self.weights = {id(m): m.weight.detach().to(half).t() for m in net.modules() if isinstance(m, nn.Linear)}
        self.norms = {id(m): (m.weight.detach().to(half), m.bias.detach().to(half))
                      for m in net.modules() if isinstance(m, nn.GroupNorm)}  # fmt: skip

    def _product(self, layer: nn.Linear, h: torch.Tensor, bias: torch.Tensor) -> torch.Tensor:
        """`h (B, in) @ W.T + bias` in bfloat16 `(B, out)`, in blocks of BF16_BLOCK_ROWS rows."""
        rows, weight = h.shape[0], self.weights[id(layer)]
        h, bias = h.to(torch.bfloat16), bias.to(torch.bfloat16).reshape(-1, weight.shape[1])  # (1 or B, out)
        pad = -rows % BF16_BLOCK_ROWS
        if pad:
            h = torch.cat([h, h.new_zeros(pad, h.shape[1])])
        if bias.shape[0] == 1:
            biases = [bias.expand(BF16_BLOCK_ROWS, -1)] * (h.shape[0] // BF16_BLOCK_ROWS)
        else:
            biases = list(torch.cat([bias, bias.new_zeros(pad, bias.shape[1])]).split(BF16_BLOCK_ROWS))
        out = h.new_empty(h.shape[0], weight.shape[1])
        for b, block, part in zip(biases, h.split(BF16_BLOCK_ROWS), out.split(BF16_BLOCK_ROWS), strict=True):
            torch.addmm(b, block, weight, out=part)
        return out[:rows]

    def _dense(self, block: DenseBlock, h: torch.Tensor, temb: torch.Tensor) -> torch.Tensor:
        """SiLU(GN(Linear(h) + Linear(temb))) in bfloat16 `(B, H)`."""
        bias = block.dense.bias + nn.functional.linear(temb, block.time_proj.weight, block.time_proj.bias)  # (1, H)
        pre = self._product(block.dense, h, bias)
        weight, shift = self.norms[id(block.norm)]
        return nn.functional.silu(group_norm(pre, block.norm.num_groups, weight, shift, block.norm.eps))

    @torch.no_grad()
    def __call__(self, x: torch.Tensor, t: torch.Tensor) -> torch.Tensor:
        """eps `(B, J, 3)` float32 for poses `x (B, J, 3)` at times `t`, `(B,)` or shared by the batch."""
        net = self.net
        temb = net.time_embedding(t.to(torch.float32))  # (1, E) for a shared time, else (B, E)
        h = self._dense(net.stem, x.reshape(x.shape[0], -1), temb)  # bfloat16
        stream = h.float()  # the residual sums in float32
        for block in net.blocks:
            assert isinstance(block, ResidualBlock)
            stream = stream + self._dense(block.second, self._dense(block.first, h, temb), temb)
            h = stream.to(torch.bfloat16)
        return self._product(net.head, h, net.head.bias).float().reshape(x.shape)
