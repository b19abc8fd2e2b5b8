"""The controllable adaptation branch (ControlNet-like): a frozen base score network plus a
trainable copy of its stem and residual blocks that talks to it through zero-initialised linears.

ALGORITHM.md section 4, with the reference's defects fixed:
- the trainable copy is taken from the base *after* its weights are loaded (the caller passes a
  loaded network), not from random weights;
- every connecting ("zero") linear starts with zero weights and biases, so the controlled
  network's output equals the base's until training moves them;
- the copy's second dense layer adds its time projection instead of overwriting its input;
- branch signals are added to the base's pre-normalisation sums, never assigned.
The base, its time MLP and its head stay frozen; the prompt is a learnable pose-sized vector
added (through a zero linear and SiLU) to the branch's input.
"""

from __future__ import annotations

import copy

import torch
from torch import nn

from .model import ScoreNet


def zero_linear(features_in: int, features_out: int) -> nn.Linear:
    layer = nn.Linear(features_in, features_out)
    nn.init.zeros_(layer.weight)
    nn.init.zeros_(layer.bias)
    return layer


class ControlledScoreNet(nn.Module):
    """eps_theta(x, t) of a frozen `base` steered by a trainable branch; same call as ScoreNet."""

    def __init__(self, base: ScoreNet, *, prompt_generator: torch.Generator | None = None) -> None:
        super().__init__()
        self.cfg = base.cfg
        dim = 3 * base.cfg.num_joints
        hidden = base.cfg.hidden
        self.branch_stem = copy.deepcopy(base.stem)
        self.branch_blocks = copy.deepcopy(base.blocks)
        self.base = base
        for p in self.base.parameters():
            p.requires_grad_(False)
        self.prompt = nn.Parameter(torch.randn(dim, generator=prompt_generator))
        self.zero_prompt = zero_linear(dim, dim)
        self.zero_stem = zero_linear(hidden, hidden)
        self.zero_blocks = nn.ModuleList(
            nn.ModuleList([zero_linear(hidden, hidden), zero_linear(hidden, hidden)]) for _ in base.blocks
        )

    def trainable_parameters(self) -> list[nn.Parameter]:
        return [p for p in self.parameters() if p.requires_grad]

    def forward(self, x: torch.Tensor, t: torch.Tensor) -> torch.Tensor:
        batch = x.shape[0]
        base = self.base
        temb = base.time_embedding(t.to(x.dtype))
        flat = x.reshape(batch, -1)
        # Branch stem, and its signal into the base's stem (taken before normalisation).
        c_pre = self.branch_stem.pre_norm(flat + nn.functional.silu(self.zero_prompt(self.prompt)), temb)
        h = base.stem.post_norm(base.stem.pre_norm(flat, temb) + self.zero_stem(c_pre))
        c = self.branch_stem.post_norm(c_pre)
        for block, branch, (zero_first, zero_second) in zip(
            base.blocks, self.branch_blocks, self.zero_blocks, strict=True
        ):
            c1_pre = branch.first.pre_norm(c, temb)
            c1 = branch.first.post_norm(c1_pre)
            c2_pre = branch.second.pre_norm(c1, temb)
            h1 = block.first.post_norm(block.first.pre_norm(h, temb) + zero_first(c1_pre))
            h = h + block.second.post_norm(block.second.pre_norm(h1, temb) + zero_second(c2_pre))
            c = c + branch.second.post_norm(c2_pre)
        return base.head(h).reshape(x.shape)
