"""Training settings (`TrainConfig`) and the named schedules of `fit-prior`, `adapt` and
`fit-augmenter`, the choices of the weights they store and of the sizes `zedo augment` gives.

Free of torch so that option parsing and `--help` can show the defaults without loading the
training code.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

from ..errors import ConfigError


@dataclass(frozen=True)
class TrainConfig:
    """Training settings. Defaults are the reference's recipe for infant priors."""

    epochs: int = 8000
    batch_size: int = 5000
    lr: float = 2e-4
    warmup_steps: int = 5000  # linear warm-up; step 0 has lr 0
    grad_clip: float = 1.0
    ema_decay: float = 0.9999
    t_min: float = 1e-5  # t ~ U(t_min, 1)
    seed: int = 0

    def __post_init__(self) -> None:
        for name in ("epochs", "batch_size", "warmup_steps", "seed"):
            value = getattr(self, name)
            if not isinstance(value, int) or isinstance(value, bool):
                raise ConfigError(f"training {name} must be an integer, got {value!r}")
        for name in ("lr", "grad_clip", "ema_decay", "t_min"):
            if not isinstance(getattr(self, name), (int, float)):
                raise ConfigError(f"training {name} must be a number, got {getattr(self, name)!r}")
        if not 0 <= self.ema_decay < 1:
            raise ConfigError(f"EMA decay must be in [0, 1), got {self.ema_decay}")
        if not 0 < self.t_min < 1:
            raise ConfigError(f"t_min must be in (0, 1), got {self.t_min}")
        if self.grad_clip < 0:
            raise ConfigError(f"gradient clipping norm must be >= 0 (0 = off), got {self.grad_clip}")
        if self.epochs < 1:
            raise ConfigError(f"epochs must be >= 1, got {self.epochs}")
        if self.batch_size < 1:
            raise ConfigError(f"batch size must be >= 1, got {self.batch_size}")
        if not (math.isfinite(self.lr) and self.lr > 0):  # inf trains to NaN weights, silently
            raise ConfigError(f"learning rate must be a finite number > 0, got {self.lr}")
        if self.warmup_steps < 0:
            raise ConfigError(f"warm-up steps must be >= 0, got {self.warmup_steps}")

    def to_dict(self) -> dict[str, float | int]:
        return asdict(self)


STRATEGIES = ("control", "finetune", "scratch")
# What a trained prior's file stores: its raw (last step) or moving-average weights, at one of these precisions
WEIGHT_CHOICES = ("raw", "ema")
STORED_DTYPES = ("float16", "float32")

# The adaptation recipe of `control` and `finetune`: the paper's objective and optimiser with a
# schedule sized for small sets. `scratch` has nothing to adapt from and keeps the core recipe
# (8000 epochs, warm-up 5000), which its short-schedule runs needed. Both were chosen on SyRIP
# training poses held out of the subset (benchmarks/accuracy/adapt_validation.py, docs/benchmarks.md).
ADAPT_TRAINING = TrainConfig(epochs=1000, batch_size=5000, warmup_steps=200)
SCRATCH_TRAINING = TrainConfig()


def default_training(strategy: str) -> TrainConfig:
    """The training settings `strategy` uses unless told otherwise."""
    if strategy not in STRATEGIES:
        raise ConfigError(f"unknown strategy {strategy!r}; choose one of {', '.join(STRATEGIES)}")
    return SCRATCH_TRAINING if strategy == "scratch" else ADAPT_TRAINING


# `zedo fit-augmenter`'s defaults.
AUGMENTER_TRAINING = TrainConfig(epochs=8, batch_size=1024, warmup_steps=200)
# The sizes `zedo augment` gives its outputs: drawn from the infant sizes its model stores, or each input's own
SCALE_MODES = ("infant", "keep")
