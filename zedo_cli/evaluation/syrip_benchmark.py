"""The paper's SyRIP benchmark: lift Test100 from ground-truth and from FiDIP-detected 2D,
score MPJPE / PA-MPJPE on the 12 limb joints (both sides centred on the hip midpoint).

Protocol (../shared/data/syrip/README.md): pseudo intrinsics f = 2000 px at the image centre;
detections are the FiDIP results for the real700 images, matched to Test100 through the
`original_file_name` of `keypoints2d_gt_real700.json`.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..data.datasets import SYRIP_FIDIP, SYRIP_REAL700, SYRIP_TEST100, PoseSet, load_syrip_3d, syrip_original_names
from ..data.keypoints import Keypoints2D
from ..data.skeleton import center_on_root
from ..errors import DataError
from ..formats import read_keypoints
from ..lifting.camera import resolve_intrinsics
from ..lifting.config import LiftConfig
from ..lifting.solver import LiftProgress, LiftResult, lift
from ..lifting.uncertainty import attach_uncertainty, bundled_calibrations
from ..prior.weights import Prior
from .metrics import pa_per_joint_error_mm, per_joint_error_mm
from .plausibility import symmetry_angle_error_deg, twin_ratio_fractions

# Published SyRIP Test100 figures (mm, 12 limb joints) to print beside ours.
PAPER_FIGURES = {
    "gt": {"ZeDO-i paper, best (augmented)": 43.6, "ZeDO-i paper, from scratch": 54.0,
           "reference code, from scratch (measured by the issue)": 50.9},
    "detected": {"ZeDO-i paper, best": 47.7, "reference code, from scratch (measured by the issue)": 54.7},
}  # fmt: skip


@dataclass
class Score:
    """Errors of one lifted set against its ground truth."""

    input_2d: str  # "gt" or "detected"
    count: int
    mpjpe_mm: float
    pa_mpjpe_mm: float
    per_joint_mm: dict[str, float]
    seconds: float  # lifting wall time
    poses_per_second: float
    # plausibility.py: fractions of poses with a twin-limb ratio over 1.3 / 1.6, symmetry-angle error
    twin_over_1_3: float = float("nan")
    twin_over_1_6: float = float("nan")
    symmetry_error_deg: float = float("nan")
    # fraction of true joints within their `uncertainty_m` radius; None: the lift had no uncertainty
    coverage: float | None = None
    not_lifted: int = 0  # poses the lift refused (NaN); the errors above are over the others


def score_poses(pred: np.ndarray, target: np.ndarray, joints: tuple[str, ...]) -> tuple[float, float, dict[str, float]]:
    """MPJPE, PA-MPJPE (mm) and per-joint MPJPE of root-relative `pred`, `target (N, J, 3)`, over
    the poses of `pred` that are finite (a person not lifted is NaN; see `lifted_rows`); NaN
    when none is."""
    scored = lifted_rows(pred)
    if not scored.any():
        return float("nan"), float("nan"), dict.fromkeys(joints, float("nan"))
    pred, target = pred[scored], target[scored]
    err = per_joint_error_mm(pred, target)
    pa = pa_per_joint_error_mm(pred, target)
    return float(err.mean()), float(pa.mean()), {j: float(e) for j, e in zip(joints, err.mean(0), strict=True)}


def lifted_rows(pred: np.ndarray) -> np.ndarray:
    """`(N,)` True for the poses of `pred (N, J, 3)` that are finite (lifted)."""
    return np.isfinite(pred).all(axis=(1, 2))


def _best_per_key(kp: Keypoints2D, keys: list[object]) -> dict[object, int]:
    """For each key (image name or id), the index of its highest-scoring instance (the first on ties)."""
    best: dict[object, int] = {}
    for i, key in enumerate(keys):
        if key not in best or (kp.scores[i] or 0.0) > (kp.scores[best[key]] or 0.0):
            best[key] = i
    return best


def _match(kp: Keypoints2D, names: list[str], truth: PoseSet, what: str) -> tuple[Keypoints2D, np.ndarray]:
    """Instances of `kp` for the ground-truth images (one per image: the highest score) and
    the ground truth in the same order."""
    best = _best_per_key(kp, list(names))
    missing = [n for n in truth.names if n not in best]
    if missing:
        raise DataError(f"{what}: no 2D keypoints for {len(missing)} test images, e.g. {missing[:3]}")
    chosen = [best[n] for n in truth.names]
    return kp.subset(chosen), truth.poses


def load_benchmark_inputs(syrip_dir: Path) -> tuple[PoseSet, dict[str, Keypoints2D]]:
    """Test100 ground truth and its two 2D inputs, in the ground truth's order."""
    truth = load_syrip_3d(syrip_dir, "test")
    gt2d = read_keypoints(syrip_dir / SYRIP_TEST100)
    gt_kp, _ = _match(gt2d, [str(n) for n in gt2d.file_names], truth, str(syrip_dir / SYRIP_TEST100))
    originals = syrip_original_names(syrip_dir / SYRIP_REAL700)
    return truth, {"gt": gt_kp, "detected": _detected_inputs(syrip_dir, truth, originals)}


def _detected_inputs(syrip_dir: Path, truth: PoseSet, originals: dict[str, str]) -> Keypoints2D:
    """FiDIP-detected 2D for the images of `truth`, in its order (one instance per image);
    `originals` maps real700 image ids to SyRIP names (`syrip_original_names`)."""
    det = read_keypoints(syrip_dir / SYRIP_FIDIP, images=syrip_dir / SYRIP_REAL700)
    det_names = [originals.get(str(i), "") for i in det.image_ids]
    det_kp, _ = _match(det, det_names, truth, str(syrip_dir / SYRIP_FIDIP))
    det_kp.file_names = list(truth.names)
    return det_kp


def load_syrip_train_inputs(syrip_dir: str | Path, names: list[str]) -> tuple[PoseSet, dict[str, Keypoints2D]]:
    """Training images `names` (SyRIP names, e.g. held out of an adaptation subset): their 3D
    ground truth and their ground-truth and FiDIP-detected 2D ("gt", "detected"), in the same
    order. Used to choose settings without looking at Test100."""
    syrip_dir = Path(syrip_dir)
    train = load_syrip_3d(syrip_dir, "train")
    row = {n: i for i, n in enumerate(train.names)}
    unknown = [n for n in names if n not in row]
    if unknown:
        raise DataError(f"{syrip_dir}: not SyRIP training images: {unknown[:3]}")
    held_out = f"{train.source}, {len(names)} held out"
    truth = PoseSet(train.poses[[row[n] for n in names]], train.skeleton, list(names), held_out)
    gt2d = read_keypoints(syrip_dir / SYRIP_REAL700)
    originals = syrip_original_names(syrip_dir / SYRIP_REAL700)
    keys = [originals.get(str(i), "") for i in gt2d.image_ids]
    kp, _ = _match(gt2d, keys, truth, str(syrip_dir / SYRIP_REAL700))
    return truth, {"gt": kp, "detected": _detected_inputs(syrip_dir, truth, originals)}


def lift_and_score(
    prior: Prior,
    truth: PoseSet,
    kp: Keypoints2D,
    config: LiftConfig,
    *,
    input_2d: str = "gt",
    device: str = "cpu",
    callback: Callable[[LiftProgress], None] | None = None,
    seed: int = 0,
) -> tuple[Score, LiftResult]:
    """Lift `kp` with `prior` and score it against `truth` (same order), timing the lift: MPJPE,
    PA-MPJPE, plausibility and, where the prior and settings have a calibration, the coverage of
    the per-joint uncertainty."""
    kp = kp.to_skeleton(prior.skeleton)
    mats, _ = resolve_intrinsics(kp.image_sizes, kp.image_ids, kp.file_names)
    start = time.perf_counter()
    res = lift(kp.xy, kp.confidence, mats, prior, config, device=device, callback=callback, seed=seed)
    seconds = time.perf_counter() - start
    res = attach_uncertainty(res, prior.sha256, prior.skeleton.joints, bundled_calibrations())
    pred = center_on_root(res.poses_camera, prior.skeleton)
    mpjpe, pa, per_joint = score_poses(pred, truth.poses, prior.skeleton.joints)
    twins = twin_ratio_fractions(pred, prior.skeleton)
    coverage = None
    if res.uncertainty_m is not None and res.lifted.any():
        within = np.linalg.norm(pred - truth.poses, axis=-1) <= res.uncertainty_m
        coverage = float(within[res.lifted].mean())
    return Score(input_2d, len(kp), mpjpe, pa, per_joint, seconds, len(kp) / seconds, twins[1.3], twins[1.6],
                 symmetry_angle_error_deg(pred, truth.poses, prior.skeleton), coverage,
                 int((~res.lifted).sum())), res  # fmt: skip


def _best_per_image(kp: Keypoints2D) -> Keypoints2D:
    """One instance per image id: the highest-scoring one."""
    return kp.subset(sorted(_best_per_key(kp, list(kp.image_ids)).values()))


def load_throughput_inputs(syrip_dir: str | Path) -> dict[str, Keypoints2D]:
    """All 700 real SyRIP images with ground-truth 2D and with FiDIP-detected 2D (one
    instance per image each): 1400 poses, enough that start-up does not dominate the rate."""
    syrip_dir = Path(syrip_dir)
    gt = _best_per_image(read_keypoints(syrip_dir / SYRIP_REAL700))
    det = _best_per_image(read_keypoints(syrip_dir / SYRIP_FIDIP, images=syrip_dir / SYRIP_REAL700))
    return {"gt": gt, "detected": det}


@dataclass
class Throughput:
    """Lifting rate over one batch (all inputs lifted in one call, as `zedo lift` would)."""

    count: int
    seconds: float
    poses_per_second: float


def measure_throughput(
    inputs: dict[str, Keypoints2D],
    prior: Prior,
    config: LiftConfig,
    *,
    device: str = "cpu",
    callback: Callable[[LiftProgress], None] | None = None,
) -> Throughput:
    """Poses per second of `lift` on all `inputs` together (model loading and file reading
    excluded; the rotation fit, the prior loop and the copies back to numpy included)."""
    kps = [kp.to_skeleton(prior.skeleton) for kp in inputs.values()]
    mats = [resolve_intrinsics(kp.image_sizes, kp.image_ids, kp.file_names)[0] for kp in kps]
    xy = np.concatenate([kp.xy for kp in kps])
    conf = np.concatenate([kp.confidence for kp in kps])
    start = time.perf_counter()
    lift(xy, conf, np.concatenate(mats), prior, config, device=device, callback=callback)
    seconds = time.perf_counter() - start
    return Throughput(len(xy), seconds, len(xy) / seconds)


def run_syrip_benchmark(
    syrip_dir: str | Path,
    prior: Prior,
    config: LiftConfig,
    *,
    inputs: tuple[str, ...] = ("gt", "detected"),
    device: str = "cpu",
    callback: Callable[[str, LiftProgress], None] | None = None,
) -> tuple[list[Score], dict[str, LiftResult]]:
    """Lift Test100 from each 2D input and score it against the weak 3D ground truth."""
    syrip_dir = Path(syrip_dir)
    if prior.skeleton.name != "syrip12":
        raise DataError(f"the SyRIP benchmark needs a syrip12 prior, not {prior.skeleton.name}")
    truth, kps = load_benchmark_inputs(syrip_dir)
    scores: list[Score] = []
    results: dict[str, LiftResult] = {}
    for key in inputs:
        on_progress = None if callback is None else (lambda p, k=key: callback(k, p))
        score, results[key] = lift_and_score(
            prior, truth, kps[key], config, input_2d=key, device=device, callback=on_progress
        )
        scores.append(score)
    return scores, results
