"""Option values every command checks before any work: numbers in their documented ranges,
choices, seeds and devices. A bad value is a ConfigError (exit 2) naming the option."""

from __future__ import annotations

import math
from collections.abc import Iterable

from ..data.datasets import SYRIP_SPLITS
from ..errors import ConfigError
from ..settings.device import check_device  # noqa: F401  (every command's --device)
from ..settings.limits import DEVICE_HELP, MAX_FPS, MAX_SEED, MAX_SIGMA_FRAMES, MAX_STEPS  # noqa: F401


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
