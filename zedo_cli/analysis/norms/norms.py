"""Comparison with typical infants (`zedo norms`, `zedo analyze --norms`): a reference built from clips
of typical infants, and each clip's distance from it.

The published comparison is the "Bayesian surprise" of Chambers et al. 2020 (their
compute_surprise.py): per feature and age bracket (10 weeks or less, over 10) a normal distribution
fitted by maximum likelihood to the reference clips; a clip's score is its summed log-likelihood over
the 38 pre-registered part-level features (left and right averaged); its z is taken against the
reference clips' own sums (their mean and sample standard deviation, over every bracket, as
published), and p is two-sided.

The extended comparison, which no published set has, is over the per-side features, left-right asymmetry indices
(log ratios of the two sides' speeds and spreads, and the clip's median 3D symmetry angle of each segment pair)
and zedo's `3d_` features: the published set averages the two sides, so a one-sided movement disorder can hide in
it (docs/movement.md has the measured difference). Its p is calibrated (calibrated.py: a conformal rank of the
clip's mean squared robust z among the reference clips', over the features reliable under a retest), so that a
typical clip gets p < 0.05 at most 1 time in 20 however heavy the features' tails; the calibrated p of the
left-right asymmetry is the same over the asymmetry features alone.

A reference stores, besides each feature's fit, every reference clip's feature values, so that a clip
missing a feature (a correlation of a still limb, say) is compared on the features it has, against the
reference sums over the same features.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from ...errors import ConfigError, InputFormatError
from ..clip.features_3d import PREFIX as PREFIX_3D
from ..clip.published_features import PREREGISTERED
from .calibrated import (
    CalibratedSurprise,
    ReliabilityEntry,
    bundled_reliability,
    compare_calibrated,
    epochs_surprise,
    reliable_features,
)

# Per-side features whose values are positive (speeds, spreads): log(left / right) is an asymmetry index.
ASYMMETRY_BASES: dict[str, tuple[str, ...]] = {
    **dict.fromkeys(("median_vel_angle", "IQR_vel_angle", "IQR_acc_angle"), ("Elbow", "Knee")),
    **dict.fromkeys(("medianvelx", "medianvely", "IQRvelx", "IQRvely", "IQRaccx", "IQRaccy", "IQRx", "IQRy"),
                    ("Wrist", "Ankle")),
    **dict.fromkeys(("3d_median_vel_angle", "3d_IQR_vel_angle", "3d_IQR_acc_angle"), ("Elbow", "Knee")),
}  # fmt: skip

_PER_SIDE = re.compile(r"^[A-Za-z_]+_[LR](Ankle|Wrist|Knee|Elbow|Hip|Shoulder)$")


_SYMMETRY_MEDIAN = re.compile(r"^symmetry_[a-z_]+_median_deg$")


def is_lift_artifact(name: str) -> bool:
    """A clip feature that counts the lift's own flagged frames (`<angle>_frames_too_fast`), not movement."""
    return bool(_LIFT_ARTIFACT.search(name))


def infant_features(values: Mapping[str, float]) -> dict[str, float]:
    """`values` without the features that measure the lift (`is_lift_artifact`)."""
    return {k: v for k, v in values.items() if not is_lift_artifact(k)}


def is_extended_feature(name: str) -> bool:
    """A feature of the extended comparison: a published per-side feature (`medianx_LAnkle`), a left-right
    correlation (`lrCorr_angle_Knee`), one of zedo's 3D features (`3d_...`), or a clip's median 3D symmetry
    angle of a segment pair (`symmetry_upper_arm_median_deg`: a left-right asymmetry index in 3D)."""
    return (name.startswith(PREFIX_3D) or name.startswith("lrCorr_") or bool(_PER_SIDE.match(name))
            or bool(_SYMMETRY_MEDIAN.match(name)))  # fmt: skip


NORMS_SCHEMA = "zedo.norms/1"
# Bump when a feature's definition or the set of features changes: a reference built with another
# version measures other things and is refused.
FEATURE_SET_VERSION = "zedo-clip-features/1"
AGE_THRESHOLD_WEEKS = 10.0  # the published brackets: age <= 10 weeks, age > 10 weeks
# Clips per age bracket a reference needs: every false-alarm figure of the comparison is measured with 20
# (docs/movement.md, "Comparison with typical infants")
MIN_REFERENCE_CLIPS = 20
# Counts of frames the analysis flagged as the lift's artifacts (a joint angle turning faster than an infant
# can): they measure the lift, not the infant, so no fit, z or comparison uses them
_LIFT_ARTIFACT = re.compile(r"_frames_too_fast$")
ALL_AGES = "all"
BRACKET_YOUNG = "<=10w"
BRACKET_OLD = ">10w"
ASYMMETRY_PREFIX = "asym_logratio_"
_MIN_SD = 1e-9  # a feature that does not vary across the reference cannot score a clip


MAX_AGE_WEEKS = 200.0


def check_age_weeks(age_weeks: float | None) -> None:
    """--age-weeks, where given, is an infant's age: 0 to 200 weeks."""
    if age_weeks is not None and not 0 <= age_weeks <= MAX_AGE_WEEKS:
        raise ConfigError(f"--age-weeks must be between 0 and {MAX_AGE_WEEKS:g} weeks, got {age_weeks:g}")


def age_bracket(age_weeks: float | None, with_ages: bool) -> str:
    """The bracket of a clip: the published split at 10 weeks, or `all` for a reference without ages."""
    if not with_ages:
        return ALL_AGES
    if age_weeks is None:
        raise ConfigError("this reference is split by age: give the infant's age with --age-weeks")
    return BRACKET_OLD if age_weeks > AGE_THRESHOLD_WEEKS else BRACKET_YOUNG


@dataclass(frozen=True)
class ClipValues:
    """The clip-level features of one person track of one result."""

    source: str
    person: int
    values: dict[str, float]
    age_weeks: float | None = None
    lifting: str | None = None  # how the result was lifted (compare.lifting_of); None: not recorded
    seconds: float | None = None  # how long the track lasts (first to last analysed frame); None: not recorded


def asymmetry_indices(values: Mapping[str, float]) -> dict[str, float]:
    """Left-right asymmetry indices: log(left / right) of each positive per-side feature (speeds,
    variabilities), e.g. `asym_logratio_median_vel_angle_Elbow`; NaN where either side is not > 0."""
    out: dict[str, float] = {}
    for base, parts in ASYMMETRY_BASES.items():
        for part in parts:
            left, right = values.get(f"{base}_L{part}", math.nan), values.get(f"{base}_R{part}", math.nan)
            ok = left > 0 and right > 0  # NaN compares False
            out[f"{ASYMMETRY_PREFIX}{base}_{part}"] = math.log(left / right) if ok else math.nan
    return out


def with_asymmetry(values: Mapping[str, float]) -> dict[str, float]:
    return {**values, **asymmetry_indices(values)}


def extended_names(values: Mapping[str, float]) -> list[str]:
    return sorted(k for k in values if is_extended_feature(k) or k.startswith(ASYMMETRY_PREFIX))


@dataclass
class FeatureFit:
    mean: float
    sd: float
    n: int


@dataclass
class Norms:
    """A reference of typical infants: per bracket and feature a normal fit, and the reference clips."""

    brackets: list[str]
    fits: dict[str, dict[str, FeatureFit]]  # bracket -> feature -> fit
    clips: list[ClipValues]
    brackets_of_clips: list[str]
    left_out: dict[str, list[str]] = field(default_factory=dict)  # bracket -> features without a usable fit
    zedo_version: str = ""
    feature_set_version: str = FEATURE_SET_VERSION

    @property
    def with_ages(self) -> bool:
        return self.brackets != [ALL_AGES]

    def clip_matrix(self, names: Sequence[str], bracket: str | None = None) -> np.ndarray:
        """(C, F) reference values of `names`, NaN where a clip lacks one; only `bracket`'s clips if given."""
        clips = [c for c, b in zip(self.clips, self.brackets_of_clips, strict=True) if bracket in (None, b)]
        return np.array([[c.values.get(n, np.nan) for n in names] for c in clips], float).reshape(len(clips), -1)


def _fit(column: np.ndarray) -> FeatureFit | None:
    x = column[np.isfinite(column)]
    if len(x) < MIN_REFERENCE_CLIPS:
        return None
    sd = float(x.std())  # maximum likelihood (scipy.stats.norm.fit), as published
    return FeatureFit(float(x.mean()), sd, int(len(x))) if sd > _MIN_SD else None


def build_norms(clips: Sequence[ClipValues], zedo_version: str) -> Norms:
    """Fit the reference. Every clip has an age (split at 10 weeks) or none has (one bracket).
    Refused: fewer than MIN_REFERENCE_CLIPS clips in a bracket, or a published feature that cannot be fitted.
    Counts of the lift's flagged frames are left out (`is_lift_artifact`)."""
    if not clips:
        raise ConfigError("no clips to build a reference from")
    aged = [c.age_weeks is not None for c in clips]
    if any(aged) and not all(aged):
        missing = sum(not a for a in aged)
        raise ConfigError(f"--age-weeks given for some clips but not {missing} others: give every clip's age or none")
    with_ages = all(aged)
    clips = [ClipValues(c.source, c.person, with_asymmetry(infant_features(c.values)), c.age_weeks, c.lifting,
                        c.seconds) for c in clips]  # fmt: skip
    of_clip = [age_bracket(c.age_weeks, with_ages) for c in clips]
    brackets = [b for b in (BRACKET_YOUNG, BRACKET_OLD, ALL_AGES) if b in of_clip]
    names = sorted(set().union(*(c.values for c in clips)))
    norms = Norms(brackets, {}, clips, of_clip, zedo_version=zedo_version)
    for bracket in brackets:
        count = of_clip.count(bracket)
        if count < MIN_REFERENCE_CLIPS:
            raise ConfigError(f"a reference needs at least {MIN_REFERENCE_CLIPS} clips per age bracket; "
                              f"bracket {bracket} has {count}")  # fmt: skip
        matrix = norms.clip_matrix(names, bracket)
        fits = {n: f for n, col in zip(names, matrix.T, strict=True) if (f := _fit(col)) is not None}
        lacking = [n for n in PREREGISTERED if n not in fits]
        if lacking:
            raise ConfigError(f"bracket {bracket}: the published feature {lacking[0]} has fewer than "
                              f"{MIN_REFERENCE_CLIPS} finite, varying values in the reference clips "
                              f"({len(lacking)} such)")  # fmt: skip
        norms.fits[bracket] = fits
        norms.left_out[bracket] = [n for n in names if n not in fits]
    return norms


def _loglik(x: np.ndarray, mean: np.ndarray, sd: np.ndarray) -> np.ndarray:
    """log N(x; mean, sd^2), the published `minus_log_pfeature` (which is, despite its name, log p)."""
    var = sd**2
    return -(0.5 * np.log(2 * np.pi * var) + (x - mean) ** 2 / (2 * var))


@dataclass(frozen=True)
class Surprise:
    """A clip's summed log-likelihood under the reference, and its z and two-sided p against the
    reference clips' own sums over the same features."""

    total: float
    z: float
    p: float
    features: int  # how many features were summed
    reference_clips: int


def _two_sided_p(z: float) -> float:
    return math.erfc(abs(z) / math.sqrt(2.0)) if math.isfinite(z) else math.nan


def _surprise(total: float, reference_totals: np.ndarray, features: int) -> Surprise:
    ref = reference_totals[np.isfinite(reference_totals)]
    sd = float(ref.std(ddof=1)) if len(ref) > 1 else math.nan  # pandas' std, as published
    z = (total - float(ref.mean())) / sd if sd > 0 else math.nan
    return Surprise(total, z, _two_sided_p(z), features, int(len(ref)))


@dataclass(frozen=True)
class Comparison:
    """One clip against a reference."""

    bracket: str
    z: dict[str, float]  # feature -> z against its bracket's fit
    published: Surprise
    extended: CalibratedSurprise  # the conformal p over the reliable extended features (calibrated.py)
    asymmetry: CalibratedSurprise  # the same over the reliable left-right asymmetry features
    not_compared: list[str]  # features the clip has no value for (left out of the sums)


def _fitted(norms: Norms, bracket: str, names: Sequence[str]) -> tuple[list[str], np.ndarray, np.ndarray]:
    fits = norms.fits[bracket]
    kept = [n for n in names if n in fits and not is_lift_artifact(n)]
    return kept, np.array([fits[n].mean for n in kept]), np.array([fits[n].sd for n in kept])


def compare(values: Mapping[str, float], norms: Norms, age_weeks: float | None,
            reliability: Sequence[ReliabilityEntry] | None = None,
            epochs: Sequence[Mapping[str, float]] | None = None) -> Comparison:  # fmt: skip
    """The clip's z per feature, its published surprise, and its calibrated p over the extended features and over
    the left-right asymmetry features, each those that `reliability` (default: the bundled file) finds reliable.
    `epochs`: the features of a long clip's epochs, each as long as the reference's clips: the z are then of the
    epochs' median values and the calibrated p of the median epoch (`epochs_surprise`); the published comparison
    stays on the whole clip, as published."""
    bracket = age_bracket(age_weeks, norms.with_ages)  # a reference split by age needs the age
    if bracket not in norms.fits:
        raise InputFormatError(f"no reference clips in the age bracket {bracket} (the reference has "
                               f"{', '.join(norms.brackets)}): this clip is outside its age brackets")  # fmt: skip
    values = with_asymmetry(infant_features(values))
    parts = [with_asymmetry(infant_features(e)) for e in epochs or ()]
    measured = _epoch_medians(values, parts) if parts else values
    fits = {n: f for n, f in norms.fits[bracket].items() if not is_lift_artifact(n)}  # an older reference has them
    z = {n: (measured[n] - f.mean) / f.sd for n, f in fits.items() if math.isfinite(measured.get(n, math.nan))}
    published = _published(values, norms, bracket)
    missing = sorted(n for n in fits if not math.isfinite(values.get(n, math.nan)))
    entries = bundled_reliability() if reliability is None else reliability
    extended = _calibrated_over(values, norms, bracket, extended_names(values), entries, parts)
    asymmetry = _calibrated_over(values, norms, bracket, [n for n in values if is_asymmetry_feature(n)], entries,
                                 parts)  # fmt: skip
    return Comparison(bracket, z, published, extended, asymmetry, missing)


def _epoch_medians(values: Mapping[str, float], epochs: Sequence[Mapping[str, float]]) -> dict[str, float]:
    """Per feature the median of the epochs' finite values; the whole clip's value for a feature no epoch has."""
    out = dict(values)
    for name in set().union(*epochs):
        x = np.array([e.get(name, math.nan) for e in epochs], float)
        if np.isfinite(x).any():
            out[name] = float(np.nanmedian(x))
    return out


def is_asymmetry_feature(name: str) -> bool:
    """A left-right asymmetry feature: a log ratio of the two sides (`asym_logratio_...`) or a clip's median 3D
    symmetry angle of a segment pair (`symmetry_forearm_median_deg`). Neither grows with a clip's length."""
    return name.startswith(ASYMMETRY_PREFIX) or bool(_SYMMETRY_MEDIAN.match(name))


def _calibrated_over(values: Mapping[str, float], norms: Norms, bracket: str, candidates: Sequence[str],
                     reliability: Sequence[ReliabilityEntry], epochs: Sequence[Mapping[str, float]] = ()
                     ) -> CalibratedSurprise:  # fmt: skip
    """The conformal p against the bracket's clips over the `candidates` the clip has and `reliability` finds
    reliable; with `epochs`, of the clip's median epoch."""
    names = reliable_features(sorted(n for n in candidates if math.isfinite(values.get(n, math.nan))), reliability)
    reference = norms.clip_matrix(names, bracket)
    if epochs:
        return epochs_surprise(np.array([[e.get(n, math.nan) for n in names] for e in epochs], float), reference)
    return compare_calibrated(values, reference, names)


def _published(values: Mapping[str, float], norms: Norms, bracket: str) -> Surprise:
    return summed_surprise(values, norms, bracket, list(PREREGISTERED))


def summed_surprise(values: Mapping[str, float], norms: Norms, bracket: str, names: list[str]) -> Surprise:
    """The clip's log-likelihood summed over `names` under its bracket's fits, against the reference clips' own
    sums (each under its bracket's fit, in sample, as published); a feature the clip lacks is left out of its sum
    and of the reference sums (pandas' sum skips NaN)."""
    names = [n for n in names if math.isfinite(values.get(n, math.nan))]
    kept, mean, sd = _fitted(norms, bracket, names)
    total = float(_loglik(np.array([values[n] for n in kept]), mean, sd).sum())
    ref_totals = np.empty(len(norms.clips))
    for b in norms.brackets:
        sel = np.array([x == b for x in norms.brackets_of_clips])
        k, m, s = _fitted(norms, b, kept)
        ref_totals[sel] = np.nansum(_loglik(norms.clip_matrix(k, b), m, s), axis=1)
    return _surprise(total, ref_totals, len(kept))
