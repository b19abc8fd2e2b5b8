"""How well the measures of `zedo analyze` survive lifting: SyRIP Test100 lifted from
ground-truth and FiDIP-detected 2D, analysed, and compared with the same measures on the weak
3D ground truth (the hand-corrected poses of Huang et al. 2022).

Per segment pair: the mean absolute symmetry-angle error (degrees) and Cohen's kappa of the
symmetric / asymmetric calls at the threshold (28 degrees); pooled over the four pairs (400
calls) as well. Per joint angle: the mean absolute error (flexion differences wrapped into
[-180, 180)). As a reference, the same comparison for the HW-HuP image model's 3D predictions,
from which the weak ground truth was hand-corrected (rows of the Test100 images only).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..analysis.analyse import all_measures, calibrated_measures
from ..analysis.pose.joint_angles import ANGLE_NAMES
from ..analysis.pose.symmetry import DEFAULT_THRESHOLD_DEG, PAIRS, measure_name
from ..analysis.uncertainty.calibration import DEFAULT_LEVEL, LEVELS, bundled_calibrations, find_calibration
from ..data.datasets import SYRIP_POSES, syrip_rows_by_name
from ..data.skeleton import Skeleton, center_on_root, convert_points, get_skeleton
from ..errors import DataError
from ..lifting.config import LiftConfig
from ..lifting.solver import LiftProgress
from ..prior.weights import Prior
from .metrics import cohen_kappa, decisive_calls
from .syrip_benchmark import lift_and_score, load_benchmark_inputs

SYRIP_HWHUP = "poses3d_hwhup.npy"


@dataclass
class SymmetryScore:
    """Agreement of one set of 3D poses with the ground truth's measures."""

    source: str  # "gt", "detected" (2D input of the lift) or "hwhup"
    count: int
    angle_error_deg: dict[str, float]  # per pair: mean |symmetry angle - truth's|
    mean_angle_error_deg: float  # over the pairs
    kappa: dict[str, float]  # per pair, calls at the threshold
    pooled_kappa: float  # the calls of all pairs together
    agreement: float  # share of equal calls, pooled
    asymmetric_share: float  # share of asymmetric calls, pooled (the truth's is in SymmetryBenchmark)
    joint_angle_error_deg: dict[str, float]  # per angle: mean |difference|
    mean_joint_angle_error_deg: float
    mpjpe_mm: float | None = None  # of the lift, for context
    # zedo analyze's calibrated estimates and calls (lifts only; None where no measure calibration holds)
    raw_mean_angle_error_deg: float | None = None  # of the measures of the lifted pose, before calibration
    interval_coverage: dict[str, float] | None = None  # per pair: share of truths inside the 90 % interval
    risk_coverage: list[dict[str, float]] | None = None  # per level: decisive share and its agreement, pooled


@dataclass
class SymmetryBenchmark:
    threshold_deg: float
    truth_asymmetric_share: float
    scores: list[SymmetryScore]


def _calls(values: np.ndarray, threshold: float) -> np.ndarray:
    return np.where(values <= threshold, "symmetric", "asymmetric")


def compare_measures(
    pred: np.ndarray, truth: np.ndarray, skeleton: Skeleton, *, threshold: float = DEFAULT_THRESHOLD_DEG,
    source: str = "pred",
) -> SymmetryScore:  # fmt: skip
    """Compare the measures of `pred` and `truth` `(N, J, 3)` (same poses, same order)."""
    return compare_measures_of(all_measures(pred, skeleton), all_measures(truth, skeleton), threshold, source)


def compare_measures_of(
    p: dict[str, np.ndarray], t: dict[str, np.ndarray], threshold: float, source: str
) -> SymmetryScore:
    """Compare measure values `p` with the truth's `t` (each `{name: (N,)}`, same cases)."""
    names = [measure_name(pair) for pair in PAIRS]
    if any(not np.isfinite(p[n]).all() or not np.isfinite(t[n]).all() for n in names):
        raise DataError(f"{source}: a symmetry angle is undefined (missing joint or zero-length segment)")
    errors = {n: float(np.abs(p[n] - t[n]).mean()) for n in names}
    kappas = {n: cohen_kappa(_calls(p[n], threshold), _calls(t[n], threshold)) for n in names}
    pc = np.concatenate([_calls(p[n], threshold) for n in names])
    tc = np.concatenate([_calls(t[n], threshold) for n in names])
    angle_err = {}
    for n in ANGLE_NAMES:
        d = np.abs((p[n] - t[n] + 180.0) % 360.0 - 180.0)
        angle_err[n] = float(np.nanmean(d)) if np.isfinite(d).any() else float("nan")
    return SymmetryScore(
        source, len(next(iter(p.values()))), errors, float(np.mean(list(errors.values()))), kappas, cohen_kappa(pc, tc),
        float((pc == tc).mean()), float((pc == "asymmetric").mean()), angle_err,
        float(np.nanmean(list(angle_err.values()))),
    )  # fmt: skip


def calibrated_scores(
    score: SymmetryScore, pred: np.ndarray, observed: np.ndarray, truth: np.ndarray, skeleton: Skeleton,
    prior_sha256: str, config: LiftConfig, threshold: float,
) -> SymmetryScore:  # fmt: skip
    """`score` of the lifted poses redone as `zedo analyze` reports them: the calibrated estimates'
    errors and calls, the intervals' coverage, and the decisive share and agreement at each level.
    Unchanged (with raw_mean_angle_error_deg set) when no measure calibration holds."""
    params = {"prior": {"sha256": prior_sha256}, "config": config.to_dict(), "temporal": {"mode": "none"},
              "camera_sources": ["pseudo"]}  # fmt: skip
    calibration, why = find_calibration(bundled_calibrations(), params, skeleton.joints)
    score.raw_mean_angle_error_deg = score.mean_angle_error_deg
    if calibration is None:
        return score
    _, est, intervals, _ = calibrated_measures(pred, observed, skeleton, calibration, why, LEVELS)
    t = all_measures(truth, skeleton)
    names = [measure_name(pair) for pair in PAIRS]
    redone = compare_measures_of(est, t, threshold, score.source)
    redone.mpjpe_mm, redone.raw_mean_angle_error_deg = score.mpjpe_mm, score.mean_angle_error_deg
    score = redone
    at90 = intervals[LEVELS.index(DEFAULT_LEVEL)]
    score.interval_coverage = {n: float(((at90[n][0] <= t[n]) & (t[n] <= at90[n][1])).mean()) for n in names}
    score.risk_coverage = []
    for level, at_level in zip(LEVELS, intervals, strict=True):
        low = np.concatenate([at_level[n][0] for n in names])
        high = np.concatenate([at_level[n][1] for n in names])
        decisive, agree = decisive_calls(low, high, np.concatenate([t[n] for n in names]), threshold)
        agreement = float(agree.sum() / decisive.sum()) if decisive.any() else float("nan")
        score.risk_coverage.append({"level": level, "decisive": float(decisive.mean()), "agreement": agreement,
                                    "calls": int(decisive.sum())})  # fmt: skip
    return score


def load_syrip_hwhup(syrip_dir: str | Path, names: list[str]) -> np.ndarray:
    """HW-HuP's 3D predictions `(N, 12, 3)` (syrip12, root-centred) for SyRIP images `names`
    (real images only; the synthetic rows are never read)."""
    syrip_dir = Path(syrip_dir)
    path = syrip_dir / SYRIP_HWHUP
    if not path.is_file():
        raise DataError(f"{path}: file not found")
    rows = syrip_rows_by_name(syrip_dir)
    raw = np.load(path, mmap_mode="r")
    selected = np.asarray(raw[[rows[n] for n in names]], dtype=np.float64)
    dst = get_skeleton("syrip12")
    poses, _ = convert_points(selected, np.ones(selected.shape[:2]), get_skeleton("lsp14"), dst)
    return center_on_root(poses, dst)


def run_symmetry_benchmark(
    syrip_dir: str | Path,
    prior: Prior,
    config: LiftConfig,
    *,
    inputs: tuple[str, ...] = ("gt", "detected"),
    threshold: float = DEFAULT_THRESHOLD_DEG,
    reference: bool = True,
    device: str = "cpu",
    callback: Callable[[str, LiftProgress], None] | None = None,
) -> SymmetryBenchmark:
    """Lift Test100 from each 2D input, analyse, and compare with the weak ground truth's measures."""
    if prior.skeleton.name != "syrip12":
        raise DataError(f"the symmetry benchmark needs a syrip12 prior, not {prior.skeleton.name}")
    if not (Path(syrip_dir) / SYRIP_POSES).is_file():
        raise DataError(f"{Path(syrip_dir) / SYRIP_POSES}: file not found (is --syrip-dir the SyRIP data folder?)")
    truth, kps = load_benchmark_inputs(Path(syrip_dir))
    skel = truth.skeleton
    scores = []
    for key in inputs:
        on_progress = None if callback is None else (lambda p, k=key: callback(k, p))
        score, res = lift_and_score(prior, truth, kps[key], config, input_2d=key, device=device, callback=on_progress)
        s = compare_measures(res.poses_camera, truth.poses, skel, threshold=threshold, source=key)
        s.mpjpe_mm = score.mpjpe_mm
        s = calibrated_scores(s, res.poses_root_relative, res.observed, truth.poses, skel, prior.sha256, config,
                              threshold)  # fmt: skip
        scores.append(s)
    if reference:
        hwhup = load_syrip_hwhup(syrip_dir, truth.names)
        scores.append(compare_measures(hwhup, truth.poses, skel, threshold=threshold, source="hwhup"))
    names = [measure_name(pair) for pair in PAIRS]
    t = all_measures(truth.poses, skel)
    share = float(np.mean(np.concatenate([t[n] > threshold for n in names])))
    return SymmetryBenchmark(threshold, share, scores)
