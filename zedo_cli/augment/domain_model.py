"""The condition-guided score network of `zedo augment`: the prior's network plus two learnable
domain tokens (adult, infant).

ALGORITHM.md section 5 leaves the injection to us. A token is a learnable vector of the time
embedding's width (512), added to the time embedding after its MLP, so every layer's time
projection sees "when in the diffusion" and "which domain" together, as the paper describes
("injected alongside the time embedding"). Tokens start as small random vectors so the two
domains differ from the first step.
"""

from __future__ import annotations

import torch
from torch import nn

from ..prior.model import ScoreNet

DOMAINS = ("adult", "infant")
TOKEN_INIT_STD = 0.1


def domain_index(name: str) -> int:
    from ..errors import ConfigError

    if name not in DOMAINS:
        raise ConfigError(f"unknown domain {name!r}; choose one of {', '.join(DOMAINS)}")
    return DOMAINS.index(name)


class DomainScoreNet(nn.Module):
    """eps_theta(x, t, domain): a ScoreNet whose time embedding carries a domain token.

    `domain` is an int (one domain for the batch) or a `(B,)` integer tensor.
    """

    def __init__(self, net: ScoreNet, *, token_generator: torch.Generator | None = None) -> None:
        super().__init__()
        self.cfg = net.cfg
        self.net = net
        self.tokens = nn.Parameter(TOKEN_INIT_STD * torch.randn(len(DOMAINS), net.cfg.embed, generator=token_generator))

    def forward(self, x: torch.Tensor, t: torch.Tensor, domain: int | torch.Tensor) -> torch.Tensor:
        temb = self.net.time_embedding(t.to(x.dtype)) + self.tokens[domain].to(x.dtype)
        return self.net.denoise(x, temb)
