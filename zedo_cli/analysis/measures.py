"""The measure registry: every measure `zedo analyze` writes, as one table of families. Each family names its
measures by a pattern (`symmetry_<pair>_deg`), and gives their unit, scope (a row per frame or per clip), family,
convention and range, and what a measure of it means. `measure_of(name)` finds a name's family (KeyError for a
name no family holds, so that a new measure cannot reach the outputs undocumented); `docs/measures.md` is the
table `registry_markdown()` writes, and a test keeps the two equal.

The published clip features of Chambers et al. 2020 and their `3d_` twins keep the published conventions (an
interior angle, 180 = straight); zedo's own joint angles measure flexion from straight (0 = straight)."""

from __future__ import annotations

import functools
import re
from dataclasses import dataclass

_PAIR = "(upper_arm|forearm|thigh|shank)"
_ANGLE = "(hip_flexion|hip_abduction|knee_flexion|shoulder_flexion|shoulder_abduction|elbow_flexion)"
_SIDE = "(left|right)"
_LR = "[LR]"
_ANGLE_PART_2D = "(Shoulder|Elbow|Hip|Knee)"  # the published 2D angles
_ANGLE_PART_3D = "(Elbow|Knee|HipFlexion|HipAbduction|ShoulderFlexion|ShoulderAbduction)"  # features_3d
_POSITION_PART = "(Ankle|Wrist)"
_PREREGISTERED_ANGLE_PART = "(Elbow|Knee)"  # the part-level angle features of the pre-registration
_PART = "(Shoulder|Elbow|Hip|Knee|Ankle|Wrist)"

# The published statistics: name -> (unit, what a value of it measures)
_ANGLE_STATS = {
    "mean_angle": ("deg", "the angle's mean over the clip"),
    "stdev_angle": (
        "sqrt(deg)",
        "the angle's spread, as the published code computes it (the square root of its standard deviation)",
    ),  # fmt: skip
    "entropy_angle": ("nats", "the entropy of the angle's distribution over the clip"),
    "median_vel_angle": ("deg/s", "the median of the angle's absolute velocity"),
    "IQR_vel_angle": ("deg/s", "the interquartile range of the angle's velocity"),
    "IQR_acc_angle": ("deg/s^2", "the interquartile range of the angle's acceleration"),
}
_POSITION_STATS = {
    "medianx": ("trunk", "the median horizontal position relative to the body (trunk lengths)"),
    "mediany": ("trunk", "the median vertical position relative to the body"),
    "IQRx": ("trunk", "the interquartile range of the horizontal position"),
    "IQRy": ("trunk", "the interquartile range of the vertical position"),
    "medianvelx": ("trunk/s", "the median horizontal speed"),
    "medianvely": ("trunk/s", "the median vertical speed"),
    "IQRvelx": ("trunk/s", "the interquartile range of the horizontal velocity"),
    "IQRvely": ("trunk/s", "the interquartile range of the vertical velocity"),
    "IQRaccx": ("trunk/s^2", "the interquartile range of the horizontal acceleration"),
    "IQRaccy": ("trunk/s^2", "the interquartile range of the vertical acceleration"),
    "meanent": ("nats", "the entropy of the positions over the clip"),
}
# The published statistics in plain words, for the report: statistic -> (what a value below the typical infants
# means, what one above means)
STAT_WORDS: dict[str, tuple[str, str]] = {
    "mean_angle": ("held at a smaller angle", "held at a larger angle"),
    "stdev_angle": ("its angle varies less", "its angle varies more"),
    "entropy_angle": ("its angles are less varied", "its angles are more varied"),
    "median_vel_angle": ("moves more slowly", "moves faster"),
    "IQR_vel_angle": ("its speed varies less", "its speed varies more"),
    "IQR_acc_angle": ("its acceleration varies less", "its acceleration varies more"),
    "medianx": ("lies further to the image's left of the body", "lies further to the image's right of the body"),
    "mediany": ("lies higher relative to the body", "lies lower relative to the body"),
    "IQRx": ("moves over a narrower range side to side", "moves over a wider range side to side"),
    "IQRy": ("moves over a narrower range up and down", "moves over a wider range up and down"),
    "medianvelx": ("moves more slowly side to side", "moves faster side to side"),
    "medianvely": ("moves more slowly up and down", "moves faster up and down"),
    "IQRvelx": ("its side-to-side speed varies less", "its side-to-side speed varies more"),
    "IQRvely": ("its up-and-down speed varies less", "its up-and-down speed varies more"),
    "IQRaccx": ("its side-to-side acceleration varies less", "its side-to-side acceleration varies more"),
    "IQRaccy": ("its up-and-down acceleration varies less", "its up-and-down acceleration varies more"),
    "meanent": ("its positions are less varied", "its positions are more varied"),
    "mean_dispersion": ("moves about less", "moves about more"),
    "lrCorr_angle": ("left and right angles move together less", "left and right angles move together more"),
    "lrCorr_x": ("left and right move together less", "left and right move together more"),
}
_PUBLISHED_ANGLE = "interior angle in the image, 180 = straight (published)"
_PUBLISHED_3D_ANGLE = "published statistic of the 3D angle: elbow and knee interior (180 = straight), hip and " \
    "shoulder flexion and abduction in the trunk's frame"  # fmt: skip


@dataclass(frozen=True)
class Measure:
    """A family of measures: their name `pattern` (and the `regex` its names match in full), unit, scope
    (`frame` or `clip`), family, convention and range, and what one means."""

    pattern: str
    regex: str
    unit: str
    scope: str
    family: str
    convention: str
    meaning: str


def _published() -> list[Measure]:
    out = []
    for stat, (unit, meaning) in _ANGLE_STATS.items():
        out += [
            Measure(f"{stat}_<L|R><part>", f"{stat}_{_LR}{_ANGLE_PART_2D}", unit, "clip", "published 2D",
                    _PUBLISHED_ANGLE, f"per side: {meaning} (Chambers et al. 2020)"),
            Measure(f"<Part>_{stat}", f"{_PREREGISTERED_ANGLE_PART}_{stat}", unit, "clip", "published 2D",
                    _PUBLISHED_ANGLE, f"left and right averaged: {meaning} (a pre-registered feature)"),
            Measure(f"3d_{stat}_<L|R><part>", f"3d_{stat}_{_LR}{_ANGLE_PART_3D}", unit, "clip", "3D clip features",
                    _PUBLISHED_3D_ANGLE, f"per side, of the lifted 3D angle: {meaning}"),
        ]  # fmt: skip
    for stat, (unit, meaning) in _POSITION_STATS.items():
        out += [
            Measure(f"{stat}_<L|R><part>", f"{stat}_{_LR}{_POSITION_PART}", unit, "clip", "published 2D",
                    "position in the body's frame, trunk lengths (published)", f"per side: {meaning}"),
            Measure(f"<Part>_{stat}", f"{_POSITION_PART}_{stat}", unit, "clip", "published 2D",
                    "position in the body's frame, trunk lengths (published)",
                    f"left and right averaged: {meaning} (a pre-registered feature)"),
        ]  # fmt: skip
    corr = "Pearson r of the left and right series, -1 to 1"
    return out + [
        Measure("lrCorr_angle_<part>", f"lrCorr_angle_{_ANGLE_PART_2D}", "r", "clip", "published 2D", corr,
                "how the left and right angles move together"),
        Measure("<Part>_lrCorr_angle", f"{_PREREGISTERED_ANGLE_PART}_lrCorr_angle", "r", "clip", "published 2D", corr,
                "the same (a pre-registered feature)"),
        Measure("lrCorr_x_<part>", f"lrCorr_x_{_PART}", "r", "clip", "published 2D", corr,
                "how the left and right horizontal positions move together"),
        Measure("<Part>_lrCorr_x", f"{_POSITION_PART}_lrCorr_x", "r", "clip", "published 2D", corr,
                "the same (a pre-registered feature)"),
        Measure("3d_lrCorr_angle_<part>", f"3d_lrCorr_angle_{_ANGLE_PART_3D}", "r", "clip", "3D clip features",
                corr, "how the left and right lifted 3D angles move together"),
        Measure("3d_mean_dispersion_<L|R><part>", f"3d_mean_dispersion_{_LR}{_POSITION_PART}", "trunk", "clip",
                "3D clip features", "trunk lengths, 0 = still",
                "the mean distance of the joint's trunk-normalised 3D position from its clip centroid"),
    ]  # fmt: skip


def _own() -> list[Measure]:
    share = "share of the frames, 0 to 1"
    return [
        Measure("symmetry_<pair>_deg", f"symmetry_{_PAIR}_deg", "deg", "frame", "symmetry",
                "0 = mirror-symmetric, to 180",
                "angle between the left segment and the right one mirrored through the body's mid-plane"),
        Measure("symmetry_<pair>_band", f"symmetry_{_PAIR}_band", "band", "frame", "symmetry", "1, 2 or 3",
                "the paper's band of the symmetry angle: 1 (< 30 deg), 2 (30 to < 60), 3 (>= 60)"),
        Measure("symmetry_<pair>_probability_asymmetric", f"symmetry_{_PAIR}_probability_asymmetric", "probability",
                "frame", "symmetry", "0 to 1",
                "the probability that the true symmetry angle exceeds the threshold, from the calibrated interval"),
        Measure("symmetry_<pair>_fraction_<call>", f"symmetry_{_PAIR}_fraction_(symmetric|asymmetric|uncertain)",
                "fraction", "clip", "symmetry", share, "the frames called symmetric, asymmetric or uncertain"),
        Measure("symmetry_<pair>_share_asymmetric", f"symmetry_{_PAIR}_share_asymmetric", "fraction", "clip",
                "symmetry", share, "the frames whose true symmetry angle exceeds the threshold (estimated)"),
        Measure("symmetry_<pair>_median_deg", f"symmetry_{_PAIR}_median_deg", "deg", "clip", "symmetry",
                "0 = mirror-symmetric", "the median of the frames' symmetry angles"),
        Measure("<side>_<angle>_deg", f"{_SIDE}_{_ANGLE}_deg", "deg", "frame", "joint angles",
                "flexion and abduction from straight: knee and elbow 0 = straight; hip and shoulder flexion in the "
                "trunk's sagittal plane from straight down the trunk, [-90, 270); abduction away from the midline",
                "the joint's angle in the lifted 3D pose"),
        Measure("<side>_<angle>_median_abs_velocity_deg_s", f"{_SIDE}_{_ANGLE}_median_abs_velocity_deg_s", "deg/s",
                "clip", "movement", ">= 0", "the median of the angle's absolute velocity"),
        Measure("<side>_<angle>_abs_velocity_iqr_deg_s", f"{_SIDE}_{_ANGLE}_abs_velocity_iqr_deg_s", "deg/s",
                "clip", "movement", ">= 0", "the interquartile range of the angle's absolute velocity"),
        Measure("<side>_<angle>_range_deg", f"{_SIDE}_{_ANGLE}_range_deg", "deg", "clip", "movement", ">= 0",
                "the angle's range over the clip (max - min)"),
        Measure("<side>_<angle>_frames_too_fast", f"{_SIDE}_{_ANGLE}_frames_too_fast", "frames", "clip",
                "lift artifacts", "a count, never compared with typical infants",
                "frames whose angle changed faster than the bound (left out of the movement features)"),
        Measure("<angle>_left_right_correlation", f"{_ANGLE}_left_right_correlation", "r", "clip", "movement",
                "Pearson r, -1 to 1", "how the left and right angles move together"),
        Measure("head_tilt_deg", "head_tilt_deg", "deg", "frame", "head",
                "(-90, 90], positive towards the infant's own left shoulder",
                "angle in the image between the eye line and the shoulder line"),
        Measure("head_turn", "head_turn", "deg", "frame", "head",
                "the face's yaw, positive to the infant's left; call left, right or midline (within 20 deg)",
                "where the head is turned"),
        Measure("head_turn_fraction_<call>", "head_turn_fraction_(left|right|midline)", "fraction", "clip", "head",
                share, "the frames with a head-turn call that are left, right or midline"),
        Measure("head_tilt_median_deg", "head_tilt_median_deg", "deg", "clip", "head", "as head_tilt_deg",
                "the median of the frames' head tilt"),
    ]  # fmt: skip


def _comparison() -> list[Measure]:
    return [
        Measure("<feature>_norm_z", r"\S+_norm_z", "z", "clip", "comparison", "standard deviations from typical",
                "the clip feature's z against the reference of typical infants (`--norms`)"),
        Measure("surprise_published_z", "surprise_published_z", "z", "clip", "comparison",
                "standard deviations from typical", "the clip's published surprise (summed log-likelihood) as a z"),
        Measure("surprise_<published|extended|asymmetry>_p", "surprise_(published|extended|asymmetry)_p", "p",
                "clip", "comparison", "0 to 1", "the p of that surprise (published: normal; extended and asymmetry: "
                "calibrated)"),
        Measure("surprise_<published|extended|asymmetry>_features", "surprise_(published|extended|asymmetry)_features",
                "features", "clip", "comparison", "a count", "how many features the surprise is over"),
        Measure("surprise_<extended|asymmetry>_score", "surprise_(extended|asymmetry)_score", "mean z^2", "clip",
                "comparison", ">= 0", "the mean squared robust z of the reliable extended (or left-right asymmetry) "
                "features"),
    ]  # fmt: skip


MEASURES: tuple[Measure, ...] = (*_own(), *_published(), *_comparison())


@functools.cache
def _compiled() -> tuple[tuple[re.Pattern[str], Measure], ...]:
    return tuple((re.compile(m.regex), m) for m in MEASURES)


def measure_of(name: str) -> Measure:
    """The family of the measure `name` (KeyError: no family holds it)."""
    for regex, m in _compiled():
        if regex.fullmatch(name):
            return m
    raise KeyError(f"{name}: a measure no family of the registry holds")


def registry_markdown() -> str:
    """The registry as the Markdown table of docs/measures.md."""
    rows = [
        "| measure | scope | unit | family | convention, range | meaning |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    rows += [f"| `{m.pattern}` | {m.scope} | {m.unit} | {m.family} | {m.convention} | {m.meaning} |" for m in MEASURES]
    return "\n".join(rows) + "\n"
