"""A prior made of several score networks trained alike with different seeds.

The lifting loop asks the prior for one noise prediction per step; an ensemble answers with the
mean of its members' predictions. Two trainings of one recipe differ by about 2 mm on SyRIP
Test100 (seed noise), and averaging their scores inside the loop removes part of that noise
(docs/uncertainty.md "Plausible skeletons", held-out figures). The members share one network config, SDE,
skeleton and template, so the ensemble is called exactly like a single `ScoreNet`.
"""

from __future__ import annotations

import torch
from torch import nn

from .model import ScoreNet

MEMBERS_PREFIX = "members."


class EnsembleScoreNet(nn.Module):
    """eps(x, t) = the mean of the members' eps_theta(x, t); same call as ScoreNet."""

    def __init__(self, members: list[ScoreNet]) -> None:
        super().__init__()
        if len(members) < 2:
            raise ValueError("an ensemble needs at least two members")
        if any(m.cfg != members[0].cfg for m in members):
            raise ValueError("the members of an ensemble must share one network config")
        self.cfg = members[0].cfg
        self.members = nn.ModuleList(members)

    def forward(self, x: torch.Tensor, t: torch.Tensor) -> torch.Tensor:
        total = self.members[0](x, t)
        for member in self.members[1:]:
            total = total + member(x, t)
        return total / len(self.members)


def ensemble_state(states: list[dict[str, torch.Tensor]]) -> dict[str, torch.Tensor]:
    """The state dict of an EnsembleScoreNet from its members' ScoreNet state dicts."""
    return {f"{MEMBERS_PREFIX}{i}.{name}": value for i, state in enumerate(states) for name, value in state.items()}
