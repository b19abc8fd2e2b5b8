"""The sub-variance-preserving (subVP) SDE in continuous time (Song et al. 2021).

beta(t) = beta_min + (beta_max - beta_min) t,  B(t) = int_0^t beta,
x_t = exp(-B/2) x_0 + sigma(t) z  with  sigma(t) = 1 - exp(-B(t))  (subVP's std, not square-rooted).
Shape-agnostic: every function broadcasts over whatever `t` is given.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import torch


@dataclass(frozen=True)
class SubVPSDE:
    """subVP SDE parameters. Defaults are the paper's (beta 0.1 -> 20, N = 1000)."""

    beta_min: float = 0.1
    beta_max: float = 20.0
    num_scales: int = 1000

    def beta(self, t: torch.Tensor) -> torch.Tensor:
        return self.beta_min + (self.beta_max - self.beta_min) * t

    def integrated_beta(self, t: torch.Tensor) -> torch.Tensor:
        """B(t) = int_0^t beta(s) ds."""
        return self.beta_min * t + 0.5 * (self.beta_max - self.beta_min) * t**2

    def mean_coeff(self, t: torch.Tensor) -> torch.Tensor:
        """Multiplier of x_0 in the marginal mean: exp(-B(t)/2)."""
        return torch.exp(-0.5 * self.integrated_beta(t))

    def sigma(self, t: torch.Tensor) -> torch.Tensor:
        """Marginal std of subVP: 1 - exp(-B(t))."""
        return -torch.expm1(-self.integrated_beta(t))

    def perturb(self, x0: torch.Tensor, t: torch.Tensor, noise: torch.Tensor) -> torch.Tensor:
        """x_t for clean `x0 (B, ...)`, times `t (B,)` and standard normal `noise` like x0."""
        shape = (-1,) + (1,) * (x0.dim() - 1)
        return self.mean_coeff(t).view(shape) * x0 + self.sigma(t).view(shape) * noise

    def score_from_noise(self, eps: torch.Tensor, t: torch.Tensor) -> torch.Tensor:
        """Score -eps / sigma(t) from a noise prediction."""
        sigma = self.sigma(t)
        if sigma.dim():
            sigma = sigma.view((-1,) + (1,) * (eps.dim() - 1))
        return -eps / sigma

    def to_dict(self) -> dict[str, float | int | str]:
        return {"type": "subvp", **asdict(self)}
