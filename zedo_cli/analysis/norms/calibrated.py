"""A p-value beside the published comparison whose false-alarm rate is what it says (`surprise_asymmetry_p`: over
the left-right asymmetry features, which do not grow with a clip's length; norms.is_asymmetry_feature).

The clip and the n reference clips are each scored by how far they lie from the other n: per feature a robust z
(the others' median and scaled median absolute deviation, floored at a quarter of their standard deviation), the
score the mean of the squared z over the features. The clip's p is its rank among the n + 1 scores: the share of
them at least as large as its own. If the clip is a typical infant's clip like the reference's (exchangeable with
them), p <= a happens with probability at most a, whatever the features' distributions (full conformal
prediction); with n = 20 the smallest p is 1/21, so p < 0.05 calls one typical clip in 21. A clip much longer
than the reference's is scored by its median epoch against medians of reference scores (`epochs_surprise`).

Only features that measure the infant reliably take part: those whose test-retest agreement (the same clip lifted
again with another seed and 1 px more detector noise) is at least `RELIABLE_ICC` in the shipped reliability file,
on every source it was measured on.
"""

from __future__ import annotations

import functools
import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ...versioned_json import PlainEntry, ShippedFile

MAD_TO_SD = 1.4826  # the median absolute deviation of a normal distribution times this is its SD
SCALE_FLOOR = 0.25  # a feature's robust scale is at least this share of its standard deviation
RELIABLE_ICC = 0.9  # the test-retest agreement (ICC(2,1)) a feature needs to take part


@dataclass(frozen=True)
class CalibratedSurprise:
    """The clip's score (mean squared robust z), its conformal p among the reference clips', and what it used."""

    score: float
    p: float
    features: int
    reference_clips: int
    epochs: int = 1  # a clip compared by its epochs (`epochs_surprise`): how many
    epoch_agreement: float = 1.0  # ... how much they agree (`epoch_agreement`; 1: as one clip)
    independent_epochs: int = 1  # ... and how many independent epochs they are worth (`effective_epochs`)


def _robust_z(row: np.ndarray, others: np.ndarray) -> np.ndarray:
    """`row`'s robust z per feature against `others (m, F)`; NaN where fewer than two others have the feature or
    they do not vary."""
    z = np.full(row.shape, np.nan)
    usable = np.isfinite(others).sum(axis=0) >= 2
    kept = others[:, usable]
    centre = np.nanmedian(kept, axis=0)
    scale = np.maximum(MAD_TO_SD * np.nanmedian(np.abs(kept - centre), axis=0), SCALE_FLOOR * np.nanstd(kept, 0))
    with np.errstate(invalid="ignore", divide="ignore"):
        z[usable] = np.where(scale > 0, (row[usable] - centre) / scale, np.nan)
    return z


def leave_one_out_scores(matrix: np.ndarray) -> np.ndarray:
    """Each row's score `(m,)` against the other rows of `matrix (m, F)`: the mean over its finite robust z of z
    squared (NaN where it has none)."""
    return np.array([_score(matrix[j], np.delete(matrix, j, axis=0)) for j in range(len(matrix))], float)


def _score(row: np.ndarray, others: np.ndarray) -> float:
    """`row`'s mean squared robust z against `others` over its finite z (NaN where it has none)."""
    return _mean_square(_robust_z(row, others))


def _mean_square(z: np.ndarray) -> float:
    """The mean of the finite z squared (NaN where none is finite): a row's score from its robust z."""
    z = z[np.isfinite(z)]
    return float(np.mean(z**2)) if len(z) else math.nan


def calibrated_surprise(clip: np.ndarray, reference: np.ndarray) -> CalibratedSurprise:
    """The clip's `(F,)` conformal p against `reference (n, F)` over the features the clip has (NaN in the
    reference: left out of that clip's medians)."""
    known = np.isfinite(clip)
    both = np.vstack([reference[:, known], clip[known][None]])
    scores = leave_one_out_scores(both)
    own = scores[-1]
    if not math.isfinite(own):
        return CalibratedSurprise(math.nan, math.nan, 0, len(reference))
    p = float(np.mean(scores[np.isfinite(scores)] >= own))
    return CalibratedSurprise(own, p, int(known.sum()), len(reference))


NULL_DRAWS = 10000  # medians drawn for an epoch-compared clip's null (a fixed seed: the same clip, the same p)


def epochs_surprise(epochs: np.ndarray, reference: np.ndarray) -> CalibratedSurprise:
    """A clip longer than the reference's clips, as its epochs `(k, F)` each as long as them: the median of the
    epochs' scores against the reference `(n, F)`, its p the share of medians of `effective_epochs` scores drawn
    from the reference clips' own (each against the others) that are at least as large. The epochs of one infant
    agree with each other more than clips of different infants (`epoch_agreement`); as many independent epochs as
    their agreement is worth is what the median of a typical clip's epochs varies like (Kish's design effect).
    Features no epoch has are left out."""
    known = np.isfinite(epochs).any(axis=0)
    ref, rows = reference[:, known], epochs[:, known]
    z = np.array([_robust_z(row, ref) for row in rows])  # (k, F): each epoch's, for its score and the agreement
    own_scores = np.array([_mean_square(row) for row in z], float)
    finite = np.isfinite(own_scores)
    if not finite.any():
        return CalibratedSurprise(math.nan, math.nan, 0, len(reference), len(epochs))
    own = float(np.median(own_scores[finite]))
    others = leave_one_out_scores(ref)
    others = others[np.isfinite(others)]
    agreement = epoch_agreement(z[finite])
    independent = effective_epochs(int(finite.sum()), agreement)
    if not len(others):  # no reference clip has a score: nothing to rank against
        return CalibratedSurprise(own, 1.0, int(known.sum()), len(reference), len(epochs), agreement, independent)
    draws = np.random.default_rng(0).integers(len(others), size=(NULL_DRAWS, independent))
    null = np.median(others[draws], axis=1)
    p = float((1 + np.sum(null >= own)) / (1 + NULL_DRAWS))
    return CalibratedSurprise(own, p, int(known.sum()), len(reference), len(epochs), agreement, independent)


def epoch_agreement(z: np.ndarray) -> float:
    """How much one clip's epochs agree beyond what typical clips do, in [0, 1], from their robust z `(k, F)` against
    the reference: one minus the median over the features of the variance of the epochs' z (a feature whose epochs
    vary as much as typical clips do has variance about 1 there; one whose epochs are alike, about 0). The
    intraclass correlation of the epochs, estimated from the clip itself."""
    with np.errstate(invalid="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # a feature with one finite epoch: no variance
        variance = np.nanvar(z, axis=0, ddof=1) if len(z) > 1 else np.full(z.shape[1:], np.nan)
    variance = variance[np.isfinite(variance)]
    return float(np.clip(1.0 - np.median(variance), 0.0, 1.0)) if len(variance) else 1.0


def effective_epochs(epochs: int, agreement: float) -> int:
    """The number of independent epochs that `epochs` epochs of intraclass correlation `agreement` are worth:
    Kish's design effect, epochs / (1 + (epochs - 1) agreement), rounded, at least 1."""
    return max(1, int(round(epochs / (1.0 + (epochs - 1) * agreement))))


class ReliabilityEntry(PlainEntry):
    """The test-retest agreement of each clip feature measured on one clip source."""

    source: str
    clips: int
    temporal_mode: str
    icc: dict[str, float]
    provenance: dict[str, str]


RELIABILITY_FILE = ShippedFile("reliability.json", "zedo-feature-reliability", 1, "sources",
                               "clip feature reliability", ReliabilityEntry)  # fmt: skip


def reliable_features(names: Sequence[str], entries: Sequence[ReliabilityEntry]) -> list[str]:
    """`names` whose ICC is at least RELIABLE_ICC on every source that measured them (one measured at least)."""

    def reliable(name: str) -> bool:
        measured = [e.icc[name] for e in entries if name in e.icc]
        return bool(measured) and all(math.isfinite(v) and v >= RELIABLE_ICC for v in measured)

    return [n for n in names if reliable(n)]


@functools.cache
def bundled_reliability() -> tuple[ReliabilityEntry, ...]:
    return RELIABILITY_FILE.read_bundled()


def compare_calibrated(values: Mapping[str, float], reference: np.ndarray, names: Sequence[str]) -> CalibratedSurprise:
    """`calibrated_surprise` of the clip's `values` over `names` (the columns of `reference (n, len(names))`)."""
    return calibrated_surprise(np.array([values.get(n, math.nan) for n in names], float), reference)
