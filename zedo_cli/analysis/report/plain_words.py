"""Clip feature names in plain words, for the report: "left elbow: moves more slowly than typical (z = -4.1)".

The names are those of `published_features` (per side `<stat>_<side><part>`, part-level `<part>_<stat>`
with the sides averaged, `lrCorr_<kind>_<part>`) and of `features_3d` (the same with `3d_` in front, and
`3d_mean_dispersion_<side><part>`). `describe(name, z)` says what a z below or above the typical infants
means; an unknown name raises KeyError, so a new feature cannot reach the report without words.
"""

from __future__ import annotations

import re

from ..clip.features_3d import PREFIX
from ..measures import STAT_WORDS

_SIDE = {"L": "left ", "R": "right "}
_PART = {
    "Ankle": "ankle", "Wrist": "wrist", "Knee": "knee", "Elbow": "elbow", "Hip": "hip", "Shoulder": "shoulder",
    "HipFlexion": "hip flexion", "HipAbduction": "hip abduction", "ShoulderFlexion": "shoulder flexion",
    "ShoulderAbduction": "shoulder abduction",
}  # fmt: skip
_STAT = STAT_WORDS
_STATS = "|".join(sorted(map(re.escape, _STAT), key=len, reverse=True))
_PARTS = "|".join(sorted(_PART, key=len, reverse=True))
_PER_SIDE = re.compile(rf"^({_STATS})_([LR]?)({_PARTS})$")  # mean_angle_LKnee, lrCorr_angle_Knee
_PART_LEVEL = re.compile(rf"^({_PARTS})_({_STATS})$")  # Knee_mean_angle (left and right averaged)


# the clip rows of zedo analyze itself (movement, symmetry, head): suffix -> (below typical, above typical)
_MOVEMENT = {
    "median_abs_velocity_deg_s": ("moves more slowly", "moves faster"),
    "abs_velocity_iqr_deg_s": ("its speed varies less", "its speed varies more"),
    "range_deg": ("moves through a smaller range", "moves through a larger range"),
    "frames_too_fast": ("fewer frames flagged too fast", "more frames flagged too fast"),
    "left_right_correlation": ("left and right move together less", "left and right move together more"),
}
_BASES = (
    r"(?:left_|right_)?(?:hip_flexion|hip_abduction|knee_flexion|shoulder_flexion|shoulder_abduction|elbow_flexion)"
)
_MOVEMENT_RE = re.compile(rf"^({_BASES})_({'|'.join(_MOVEMENT)})$")
_SYMMETRY_RE = re.compile(r"^symmetry_(upper_arm|forearm|thigh|shank)_(share_asymmetric|fraction_\w+|median_deg)$")
_HEAD = {
    "head_turn_fraction_left": ("head turned left in fewer frames", "head turned left in more frames"),
    "head_turn_fraction_right": ("head turned right in fewer frames", "head turned right in more frames"),
    "head_turn_fraction_midline": ("head at the midline in fewer frames", "head at the midline in more frames"),
    "head_tilt_median_deg": ("head tilted less", "head tilted more"),
}
ASYMMETRY_PREFIX = "asym_logratio_"  # analysis.norms: log(left / right) of a per-side feature


def _own_rows(name: str) -> tuple[str, tuple[str, str]] | None:
    """(what, (below, above)) for the clip rows of zedo analyze (not the published / 3d_ features)."""
    if m := _MOVEMENT_RE.match(name):
        return m[1].replace("_", " "), _MOVEMENT[m[2]]
    if m := _SYMMETRY_RE.match(name):
        pair, stat = m[1].replace("_", " "), m[2]
        if stat == "median_deg":
            return f"{pair} symmetry", ("median symmetry angle smaller", "median symmetry angle larger")
        call = "asymmetric" if stat == "share_asymmetric" else stat.removeprefix("fraction_")
        return f"{pair} symmetry", (f"{call} in fewer frames", f"{call} in more frames")
    if name in _HEAD:
        return "head", _HEAD[name]
    if name.startswith(ASYMMETRY_PREFIX):
        stat, where, is_3d = _parse(name.removeprefix(ASYMMETRY_PREFIX))
        low, high = _STAT[stat]
        where = where.removesuffix(" (both sides)")
        return (
            f"{where}{' (3D)' if is_3d else ''}, left against right",
            (f"on the left, {low} (relative to the right)", f"on the left, {high} (relative to the right)"),
        )
    return None


def _parse(name: str) -> tuple[str, str, bool]:
    """(statistic, body part in words, 3D) of a feature name; KeyError for a name without words."""
    is_3d = name.startswith(PREFIX)
    bare = name.removeprefix(PREFIX)
    if m := _PER_SIDE.match(bare):
        stat, side, part = m.groups()
        where = _SIDE.get(side, "") + _PART[part] if side or stat.startswith("lrCorr") else _PART[part]
        if not side and not stat.startswith("lrCorr"):
            where = _PART[part] + "s (both sides)"
        return stat, where, is_3d
    if m := _PART_LEVEL.match(bare):
        part, stat = m.groups()
        return stat, _PART[part] + "s (both sides)", is_3d
    raise KeyError(f"no plain words for the feature {name!r}")


def describe(name: str, z: float) -> str:
    """`left elbow: moves more slowly than typical (z = -4.1)`; `(3D)` marks a feature of the lifted poses."""
    if (own := _own_rows(name)) is not None:
        where, (low, high) = own
        return f"{where}: {low if z < 0 else high} than typical (z = {z:+.1f})"
    stat, where, is_3d = _parse(name)
    low, high = _STAT[stat]
    what = low if z < 0 else high
    return f"{where}{' (3D)' if is_3d else ''}: {what} than typical (z = {z:+.1f})"


def has_words(name: str) -> bool:
    """Whether `describe` knows the feature."""
    try:
        _own_rows(name) or _parse(name)
    except KeyError:
        return False
    return True
