"""Denoising score matching: the loss and the training loop (Adam, warm-up, clipping, EMA).

ALGORITHM.md section 2.4. No prints and no paths: progress goes through a callback.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field

import torch
from torch import nn

from ..errors import ConfigError
from .schedules import TrainConfig
from .sde import SubVPSDE


@dataclass(frozen=True)
class TrainProgress:
    epoch: int  # 1-based, finished epochs
    epochs: int
    step: int
    loss: float  # mean loss of the epoch
    # The current "raw" or "ema" weights as a fresh state dict (like TrainResult.state), for
    # callers that keep snapshots mid-training.
    snapshot: Callable[[str], dict[str, torch.Tensor]] | None = None


@dataclass
class TrainResult:
    """Raw (last-step) weights and their exponential moving average, both as state dicts."""

    raw_state: dict[str, torch.Tensor]
    ema_state: dict[str, torch.Tensor]
    steps: int
    final_loss: float
    seconds: float
    loss_history: list[float] = field(default_factory=list)

    def state(self, weights: str) -> dict[str, torch.Tensor]:
        """The raw ("raw") or averaged ("ema") weights."""
        return self.raw_state if weights == "raw" else self.ema_state

    def summary(self) -> dict[str, float | int]:
        """Steps, final loss and seconds, for a weights file's training metadata."""
        return {"steps": self.steps, "final_loss": round(self.final_loss, 5), "seconds": round(self.seconds, 1)}


def dsm_loss(
    model: nn.Module,
    sde: SubVPSDE,
    x0: torch.Tensor,
    t: torch.Tensor,
    noise: torch.Tensor,
    labels: torch.Tensor | None = None,
) -> torch.Tensor:
    """Noise-prediction loss: 1/2 sum over the 3J dims of (eps_theta(x_t, t) - z)^2, batch mean.

    Summed rather than averaged over dims, as the reference does (`reduce_mean = False`).
    `labels`, when given, is the per-pose condition passed to a conditional model as a third
    argument (the domain of `zedo augment`'s network).
    """
    xt = sde.perturb(x0, t, noise)
    eps = model(xt, t) if labels is None else model(xt, t, labels)
    err = eps - noise
    return 0.5 * err.pow(2).flatten(1).sum(dim=1).mean()


class EMA:
    """Exponential moving average of parameters with the reference's warm-up:
    decay_n = min(decay, (1 + n) / (10 + n))."""

    def __init__(self, params: Iterable[nn.Parameter], decay: float) -> None:
        self.params = [p for p in params if p.requires_grad]
        self.shadow = [p.detach().clone() for p in self.params]
        self.decay = decay
        self.updates = 0

    @torch.no_grad()
    def update(self) -> None:
        self.updates += 1
        decay = min(self.decay, (1 + self.updates) / (10 + self.updates))
        for s, p in zip(self.shadow, self.params, strict=True):
            s.lerp_(p.detach(), 1.0 - decay)

    def state_dict_of(self, model: nn.Module) -> dict[str, torch.Tensor]:
        """The model's state dict with trainable parameters replaced by their averages."""
        by_id = {id(p): s for p, s in zip(self.params, self.shadow, strict=True)}
        state = {}
        for name, p in model.named_parameters():
            state[name] = by_id.get(id(p), p).detach().clone()
        for name, b in model.named_buffers():
            state[name] = b.detach().clone()
        return state


def train_score_model(
    model: nn.Module,
    sde: SubVPSDE,
    poses: torch.Tensor,
    cfg: TrainConfig,
    *,
    device: str = "cpu",
    callback: Callable[[TrainProgress], None] | None = None,
    augment: Callable[[torch.Tensor, torch.Generator], torch.Tensor] | None = None,
    labels: torch.Tensor | None = None,
) -> TrainResult:
    """Train `model` in place on root-relative poses `(N, J, 3)` in metres.

    Only parameters with `requires_grad` are optimised (adaptation freezes a base this way).
    `augment`, when given, transforms every batch before noising (e.g. random rotations),
    drawing from the training generator so runs stay reproducible. `labels (N,)`, when given,
    are integer conditions that follow their poses into every batch (see `dsm_loss`).
    Randomness (shuffling, t, noise, dropout) is seeded by `cfg.seed`; the global RNG state
    is restored afterwards.
    """
    if poses.dim() != 3 or poses.shape[-1] != 3 or poses.shape[0] == 0:
        raise ConfigError(f"training poses must have shape (N>0, J, 3), got {tuple(poses.shape)}")
    if not torch.isfinite(poses).all():
        raise ConfigError("training poses contain NaN or infinite values")
    if labels is not None and labels.shape != poses.shape[:1]:
        raise ConfigError(f"training labels must have shape ({poses.shape[0]},), got {tuple(labels.shape)}")
    start = time.perf_counter()
    data = poses.to(device=device, dtype=torch.float32)
    label_data = None if labels is None else labels.to(device=device, dtype=torch.long)
    model.to(device).train()
    params = [p for p in model.parameters() if p.requires_grad]
    optimizer = torch.optim.Adam(params, lr=cfg.lr, betas=(0.9, 0.999), eps=1e-8)
    ema = EMA(params, cfg.ema_decay)
    gen = torch.Generator(device=device).manual_seed(cfg.seed)
    n = data.shape[0]
    step = 0

    def snapshot(weights: str) -> dict[str, torch.Tensor]:
        if weights == "ema":
            return {k: v.cpu() for k, v in ema.state_dict_of(model).items()}
        return {k: v.detach().cpu().clone() for k, v in model.state_dict().items()}

    history: list[float] = []
    with torch.random.fork_rng(devices=[] if device == "cpu" else None):
        torch.manual_seed(cfg.seed)  # dropout draws from the global RNG, restored on exit
        for epoch in range(cfg.epochs):
            order = torch.randperm(n, generator=gen, device=device)
            losses = []
            for lo in range(0, n, cfg.batch_size):
                rows = order[lo : lo + cfg.batch_size]
                x0 = data[rows]
                if augment is not None:
                    x0 = augment(x0, gen)
                t = cfg.t_min + (1.0 - cfg.t_min) * torch.rand(x0.shape[0], generator=gen, device=device)
                noise = torch.randn(x0.shape, generator=gen, device=device)
                lr = cfg.lr * min(step / cfg.warmup_steps, 1.0) if cfg.warmup_steps else cfg.lr
                for group in optimizer.param_groups:
                    group["lr"] = lr
                optimizer.zero_grad(set_to_none=True)
                loss = dsm_loss(model, sde, x0, t, noise, None if label_data is None else label_data[rows])
                loss.backward()
                if cfg.grad_clip > 0:
                    nn.utils.clip_grad_norm_(params, cfg.grad_clip)
                optimizer.step()
                ema.update()
                step += 1
                losses.append(loss.item())
            history.append(sum(losses) / len(losses))
            if callback is not None:
                callback(TrainProgress(epoch + 1, cfg.epochs, step, history[-1], snapshot))
    model.eval()
    return TrainResult(snapshot("raw"), snapshot("ema"), step, history[-1], time.perf_counter() - start, history)
