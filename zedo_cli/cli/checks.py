"""Option values every command checks before any work: numbers in their documented ranges,
choices, seeds and devices. A bad value is a ConfigError (exit 2) naming the option."""

from __future__ import annotations

import math
from collections.abc import Iterable

from ..data.datasets import SYRIP_SPLITS
from ..errors import ConfigError, plural

MAX_SEED = 2**63 - 1  # torch and numpy take seeds in [0, 2**63)
MAX_STEPS = 100_000  # prior / diffusion steps: 100x faithful's 1000
MAX_COUNT = 1_000_000  # poses written by `zedo augment`
MAX_SIGMA_FRAMES = 1_000.0  # the temporal filter's width: a window of 6000 frames
MAX_FPS = 100_000.0
DEVICE_HELP = "cpu, cuda, cuda:N or auto (CUDA when torch sees a GPU, else cpu)."  # --device of every command


def check_range(
    option: str, value: float | None, low: float, high: float, *, low_open: bool = False, unit: str = ""
) -> None:
    """`value` (None: not given) is a finite number in [low, high] ((low, high] with `low_open`)."""
    if value is None:
        return
    above_low = value > low if low_open else value >= low
    if not (isinstance(value, int) or math.isfinite(value)) or not above_low or value > high:
        bracket = "(" if low_open else "["
        raise ConfigError(f"{option} must be in {bracket}{_number(low)}, {_number(high)}]{unit}, got {_number(value)}")


def _number(x: float) -> str:
    """Integers in full (a seed bound, a step count), other numbers compactly."""
    return str(int(x)) if isinstance(x, int) or (math.isfinite(x) and x.is_integer() and abs(x) < 1e16) else f"{x:g}"


def check_seed(seed: int | None) -> None:
    check_range("--seed", seed, 0, MAX_SEED)


def check_steps(steps: int | None, option: str = "--steps") -> None:
    check_range(option, steps, 1, MAX_STEPS)


def check_choice(option: str, value: str, choices: Iterable[str]) -> None:
    choices = tuple(choices)
    if value not in choices:
        raise ConfigError(f"{option} must be one of {', '.join(choices)}, got {value!r}")


def check_syrip_split(split: str, option: str = "--split") -> None:
    check_choice(option, split, SYRIP_SPLITS)


def check_device(device: str) -> str:
    """The device to run on: `cpu`, `cuda` / `cuda:N` when torch sees that GPU, `mps` where
    available, or `auto` (CUDA when torch sees a GPU, else the CPU)."""
    import torch

    if device == "auto":
        return "cuda" if torch.cuda.is_available() else "cpu"
    try:
        dev = torch.device(device)
    except (RuntimeError, ValueError):
        raise ConfigError(f"--device must be cpu, cuda, cuda:N or auto, got {device!r}") from None
    if dev.type == "cpu":
        return device
    if dev.type == "cuda":
        if not torch.cuda.is_available():
            raise ConfigError(f"--device {device}: no CUDA GPU is available to this torch ({torch.__version__}); "
                              "use --device cpu")  # fmt: skip
        if dev.index is not None and dev.index >= torch.cuda.device_count():
            raise ConfigError(f"--device {device}: torch sees {plural(torch.cuda.device_count(), 'CUDA GPU')}")
        return device
    if dev.type == "mps" and torch.backends.mps.is_available():
        return device
    raise ConfigError(f"--device must be cpu, cuda, cuda:N or auto, got {device!r}")
