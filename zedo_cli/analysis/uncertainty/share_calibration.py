"""The clip share's calibration across sources (`zedo_cli/weights/share.json`).

A clip's share of frames asymmetric is the mean of its frames' calibrated probabilities; its block bootstrap
(clip_share.py) says how far the frames' own uncertainty lets it move, and narrows as the clip grows. Where the
frames' calibration is biased for a clip's kind of poses or motion, that bias does not shrink with length. This
calibration bounds the share's error as measured on whole clips of several sources and lengths: per symmetry pair,
threshold and level, the split-conformal quantile `margin` of |estimate - true share|. The share's interval is the
hull of the bootstrap interval and estimate +- margin, within [0, 1].

A threshold between two calibrated thresholds takes the larger of their margins; outside them there is none.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from typing import Protocol

import numpy as np

from ...versioned_json import PlainEntry, ShippedFile
from .clip_share import Share


class ShareMargin(PlainEntry):
    """The margin of one symmetry pair's share at one threshold and level, and what backs it."""

    pair: str  # symmetry_<pair>
    threshold_deg: float
    level: float
    margin: float
    cases: int  # (clip, pair) cases the quantile was taken over
    sources: list[str]
    provenance: dict[str, str]


SHARE_FILE = ShippedFile("share.json", "zedo-share-calibration", 1, "margins", "share calibration", ShareMargin)
SHARE_CALIBRATED = "block_bootstrap_and_share_calibration"  # the `interval` code of a share with a margin


@functools.cache
def bundled_share_margins() -> tuple[ShareMargin, ...]:
    return SHARE_FILE.read_bundled()


def share_margin(margins: Sequence[ShareMargin], pair: str, threshold_deg: float, level: float) -> ShareMargin | None:
    """The margin that holds for `pair` at `threshold_deg` and `level`: the calibrated threshold's, or the larger of
    the two calibrated thresholds around it; None outside them (or for an uncalibrated pair or level)."""
    mine = sorted((m for m in margins if m.pair == pair and m.level == level), key=lambda m: m.threshold_deg)
    below = [m for m in mine if m.threshold_deg <= threshold_deg]
    above = [m for m in mine if m.threshold_deg >= threshold_deg]
    if not below or not above:
        return None
    return max(below[-1], above[0], key=lambda m: m.margin)


def calibrated_thresholds(margins: Sequence[ShareMargin]) -> tuple[float, float] | None:
    """The range of thresholds the margins cover (None: no margins)."""
    values = [m.threshold_deg for m in margins]
    return (min(values), max(values)) if values else None


class _Levels(Protocol):
    threshold_deg: float
    level: float


def calibrated_share(share: Share | None, pair: str, settings: _Levels, counted: int, total: int
                     ) -> tuple[float, float, float, str]:  # fmt: skip
    """A person's share of frames asymmetric as its clip row states it: value, low, high and the `interval` code,
    from its block bootstrap `share` over the `counted` of `total` frames with a calibrated value (None: none),
    widened by the bundled margin for `pair` at the settings' threshold and level; no interval where none holds."""
    if share is None:
        return np.nan, np.nan, np.nan, "none: no frame has a calibrated value"
    margins = bundled_share_margins()
    held = share_margin(margins, pair, settings.threshold_deg, settings.level)
    if held is None:
        covered = calibrated_thresholds(margins)
        where = "no share calibration" if covered is None else f"thresholds {covered[0]:g}-{covered[1]:g} deg only"
        return share.value, np.nan, np.nan, f"none: {where}"
    low = max(0.0, min(share.low, share.value - held.margin))
    high = min(1.0, max(share.high, share.value + held.margin))
    how = SHARE_CALIBRATED if counted == total else (
        f"{SHARE_CALIBRATED}: over {counted} of {total} frames (the others have no calibrated value)")  # fmt: skip
    return share.value, low, high, how
