"""Option values checked before any work by the commands without a settings model: numbers in their
documented ranges and devices. A bad value is a ConfigError (exit 2) naming the option."""

from __future__ import annotations

import math

from ..errors import ConfigError
from ..settings.device import check_device  # noqa: F401  (re-exported: --device)
from ..settings.limits import DEVICE_HELP, MAX_STEPS  # noqa: F401  (DEVICE_HELP re-exported)


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


def check_steps(steps: int | None, option: str = "--steps") -> None:
    check_range(option, steps, 1, MAX_STEPS)
