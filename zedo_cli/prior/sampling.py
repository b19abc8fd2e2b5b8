"""Reverse-time steps of the diffusion prior. The sampler does not know the network: it takes
a noise prediction."""

from __future__ import annotations

from collections.abc import Callable

import torch

from .sde import SubVPSDE


def probability_flow_step(
    x: torch.Tensor, eps: torch.Tensor, t: torch.Tensor, sde: SubVPSDE, delta: float, flow: float
) -> torch.Tensor:
    """One reverse Euler step of the probability-flow ODE from noise prediction `eps`.

    x <- x - delta * (f - flow * g^2 * score), with f = -beta x / 2, score = -eps / sigma and
    g^2 / sigma = beta (1 + exp(-B)), i.e.
    x <- (1 + beta delta / 2) x - flow * delta * beta (1 + exp(-B)) eps.
    The reference (ZeDO-i, inherited from GFPose) uses flow = 1.0, not the textbook 0.5, and a
    fixed delta = 1/N independent of the spacing of t (ALGORITHM.md 3.5c).
    """
    beta = sde.beta(t)
    coeff = flow * delta * beta * (1.0 + torch.exp(-sde.integrated_beta(t)))
    return (1.0 + 0.5 * beta * delta) * x - coeff * eps


def diffusion_scale(t: torch.Tensor, sde: SubVPSDE, dt: float) -> torch.Tensor:
    """g(t) sqrt(dt): the standard deviation of the reverse SDE's noise over a step dt."""
    return torch.sqrt(sde.beta(t) * -torch.expm1(-2.0 * sde.integrated_beta(t)) * dt)


def euler_maruyama_step(
    x: torch.Tensor, eps: torch.Tensor, t: torch.Tensor, sde: SubVPSDE, dt: float, noise: torch.Tensor
) -> torch.Tensor:
    """One reverse-time Euler-Maruyama step of the SDE (dt > 0 is the step towards t = 0):
    x <- x - (f - g^2 score) dt + g sqrt(dt) z, with g^2 = beta (1 - exp(-2B))."""
    beta = sde.beta(t)
    big_b = sde.integrated_beta(t)
    g2 = beta * -torch.expm1(-2.0 * big_b)
    score = -eps / sde.sigma(t)
    drift = -0.5 * beta * x - g2 * score
    return x - drift * dt + torch.sqrt(g2 * dt) * noise


@torch.no_grad()
def integrate_reverse_sde(
    eps_fn: Callable[[torch.Tensor, torch.Tensor], torch.Tensor],
    sde: SubVPSDE,
    x: torch.Tensor,
    *,
    t_start: float,
    t_end: float,
    steps: int,
    generator: torch.Generator,
    on_step: Callable[[], None] | None = None,
) -> torch.Tensor:
    """Integrate the reverse SDE from `t_start` down to `t_end` in `steps` Euler-Maruyama steps,
    starting at `x`; `eps_fn(x, t)` is the noise prediction. Seeded by `generator`; `on_step`
    is called after every step (progress)."""
    ts = torch.linspace(t_start, t_end, steps + 1)
    dt = (t_start - t_end) / steps
    for t in ts[:-1]:
        eps = eps_fn(x, t)
        x = euler_maruyama_step(x, eps, t, sde, dt, torch.randn(x.shape, generator=generator))
        if on_step is not None:
            on_step()
    return x


@torch.no_grad()
def sample_poses(
    model: torch.nn.Module,
    sde: SubVPSDE,
    shape: tuple[int, ...],
    *,
    steps: int = 1000,
    t_min: float = 1e-3,
    generator: torch.Generator,
) -> torch.Tensor:
    """Unconditional samples `shape = (N, J, 3)` from the prior: start from N(0, sigma(1)^2),
    integrate the reverse SDE from t = 1 to `t_min` by Euler-Maruyama (`steps` time points).
    Seeded by `generator`."""
    x = sde.sigma(torch.tensor(1.0)) * torch.randn(shape, generator=generator)
    return integrate_reverse_sde(model, sde, x, t_start=1.0, t_end=t_min, steps=steps - 1, generator=generator)
