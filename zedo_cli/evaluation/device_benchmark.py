"""The device benchmark (`zedo benchmark --scale`): lift throughput and peak memory for
large batches on one device, CPU/device agreement on the same poses, and `fit-prior` time.

The inputs are synthetic: 3D poses from a pool (SyRIP's 600 training poses, never Test100; or
poses sampled from the prior), each turned by a small random rotation, placed in front of the
pseudo camera (f = 2000 px at the centre of a 1920 x 1440 image) and projected, with 1 px of
pixel noise. Pose i is drawn from a random stream seeded by the seed and i's block of
`INPUT_BLOCK` poses, so the first M poses of a batch of N are the same for every N >= M: the
agreement run reuses the device's lift of the first batch.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
import torch

from ..data.datasets import PoseSet, load_syrip_3d
from ..errors import ConfigError
from ..lifting.camera import PSEUDO_FOCAL_PX, Intrinsics
from ..lifting.config import LiftConfig
from ..lifting.result import LiftResult
from ..lifting.solver import LIFTED, LiftProgress, lift
from ..prior.recipes import Recipe, fit_prior, with_overrides
from ..prior.sampling import sample_poses
from ..prior.training import TrainProgress
from ..prior.weights import Prior, load_prior

IMAGE_SIZE = (1920, 1440)  # the synthetic inputs' image (width, height); the pseudo camera at its centre
INPUT_BLOCK = 4096  # poses per random stream of the synthetic inputs
MAX_TURN_RAD = 0.3  # each axis of the random rotation, uniform in +-this
DEPTH_RANGE_M = (1.5, 2.5)  # the root's distance from the camera: the body's 2D fits in the image
PIXEL_NOISE_PX = 1.0
POOL_SAMPLES = 512  # poses sampled from the prior when no SyRIP folder is given
POOL_SAMPLE_STEPS = 500
# Agreement: thresholds on the largest joint distance of two root-relative poses (metres).
AGREE_TIGHT_M, AGREE_LOOSE_M = 0.001, 0.010
# A bone's depth component that changes sign between two lifts, by at least this much on each
# side (metres), is a depth flip of that segment (the 2D cannot tell the two apart).
FLIP_MIN_DEPTH_M = 0.005
# Classes of a pose pair (`classify_pairs`).
CLASSES = ("within_1mm", "within_10mm", "same_refusal", "status_differs", "depth_flip", "other_over_10mm")


@dataclass(frozen=True)
class ScaleSettings:
    """What `run_device_benchmark` measures."""

    sizes: tuple[int, ...] = (100_000, 1_000_000)  # batch sizes timed on the device
    agreement_poses: int = 100_000  # the first this many poses are lifted on the CPU too (0: skip)
    fit_epochs: int = 200  # epochs of the recipe's training timed (0: skip)
    seed: int = 0

    def __post_init__(self) -> None:
        if not self.sizes or any(n < 1 for n in self.sizes):
            raise ConfigError(f"--scale sizes must be whole numbers >= 1, got {list(self.sizes)}")
        if self.agreement_poses < 0 or self.fit_epochs < 0:
            raise ConfigError("agreement poses and fit epochs must be >= 0")
        if self.fit_epochs == 1:
            raise ConfigError("--fit-epochs must be 0 (skip) or at least 2: the first epoch is not timed")


@dataclass
class LiftRun:
    """One timed lift of `count` synthetic poses."""

    count: int
    seconds: float
    poses_per_second: float
    lifted: int  # poses lifted (the others refused, with a status)
    chunk_rows: int  # LiftConfig.chunk_size
    peak_memory_mib: float | None  # see `memory_kind`; None where it could not be read
    memory_kind: str  # "cuda max_memory_allocated" or "host peak RSS (VmHWM)"


@dataclass
class Agreement:
    """The same poses lifted on the CPU and on a device, pose by pose."""

    poses: int
    both_lifted: int
    share_within_1mm: float  # of all poses: both lifted within 1 mm, or both refused for the same reason
    share_within_10mm: float
    counts: dict[str, int]  # per class of CLASSES
    flipped_segments: dict[str, int]  # "elbow-wrist" segment -> poses where its depth flipped
    largest: list[dict[str, object]] = field(default_factory=list)  # the largest differences (none: all equal)


@dataclass
class FitTiming:
    """A short training run of a recipe, timed and extrapolated to the recipe's epochs."""

    poses: int
    epochs_run: int
    steps_per_epoch: int
    seconds_per_epoch: float  # epochs 2.. (the first, with the device's start-up, not counted)
    recipe_epochs: int
    extrapolated_seconds: float  # seconds_per_epoch x recipe_epochs: an estimate, not a measurement


@dataclass
class DeviceReport:
    device: str
    pose_source: str
    preset: str
    runs: list[LiftRun]
    agreement: Agreement | None
    fit: FitTiming | None


def pose_pool(prior: Prior, syrip_dir: str | Path | None, seed: int = 0) -> PoseSet:
    """Root-relative 3D poses `(P, J, 3)` the synthetic inputs are made from: SyRIP's 600 training
    poses (`syrip_dir`; never Test100), else POOL_SAMPLES poses sampled from `prior` on the CPU."""
    if syrip_dir is not None:
        if prior.skeleton.name != "syrip12":
            raise ConfigError(f"SyRIP poses are syrip12; the prior's joint set is {prior.skeleton.name}")
        return load_syrip_3d(syrip_dir, "train")
    if prior.template.device.type != "cpu":
        raise ConfigError("pose_pool samples on the CPU: give it the prior loaded on the CPU")
    gen = torch.Generator().manual_seed(seed)
    model = prior.model
    shape = (POOL_SAMPLES, prior.skeleton.num_joints, 3)
    poses = sample_poses(model, prior.sde, shape, steps=POOL_SAMPLE_STEPS, generator=gen).double().numpy()
    poses = poses - poses[:, prior.skeleton.root_indices].mean(axis=1, keepdims=True)
    names = [f"prior sample {i}" for i in range(len(poses))]
    return PoseSet(poses, prior.skeleton, names, f"{POOL_SAMPLES} poses sampled from {Path(prior.path).name}")


def _rotations(angles: np.ndarray) -> np.ndarray:
    """Rotations `(n, 3, 3)` about x, then y, then z by `angles (n, 3)` radians."""
    c, s = np.cos(angles), np.sin(angles)
    n = len(angles)
    rx, ry, rz = (np.zeros((n, 3, 3)) for _ in range(3))
    rx[:, 0, 0], rx[:, 1, 1], rx[:, 1, 2], rx[:, 2, 1], rx[:, 2, 2] = 1, c[:, 0], -s[:, 0], s[:, 0], c[:, 0]
    ry[:, 1, 1], ry[:, 0, 0], ry[:, 0, 2], ry[:, 2, 0], ry[:, 2, 2] = 1, c[:, 1], s[:, 1], -s[:, 1], c[:, 1]
    rz[:, 2, 2], rz[:, 0, 0], rz[:, 0, 1], rz[:, 1, 0], rz[:, 1, 1] = 1, c[:, 2], -s[:, 2], s[:, 2], c[:, 2]
    return rz @ ry @ rx


def synthetic_inputs(pool: np.ndarray, count: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pixels `(count, J, 2)`, confidences `(count, J)` (all 1) and intrinsics `(count, 3, 3)` of
    poses from `pool (P, J, 3)`, turned, placed and projected through the pseudo camera (module
    docstring). The first M rows do not depend on `count`."""
    k = Intrinsics.pseudo(*IMAGE_SIZE).matrix()  # (3, 3) the pseudo camera of the synthetic inputs
    joints = pool.shape[1]
    xy = np.empty((count, joints, 2))
    for start in range(0, count, INPUT_BLOCK):
        n = min(INPUT_BLOCK, count - start)
        # a whole block's draws, whatever part of it is used: the first rows do not depend on `count`
        rng = np.random.default_rng([seed, start // INPUT_BLOCK])
        which = rng.integers(0, len(pool), INPUT_BLOCK)[:n]
        angles = rng.uniform(-MAX_TURN_RAD, MAX_TURN_RAD, (INPUT_BLOCK, 3))[:n]
        depth = rng.uniform(*DEPTH_RANGE_M, INPUT_BLOCK)[:n]
        centre = rng.uniform(-0.15, 0.15, (INPUT_BLOCK, 2))[:n]  # the root near the image's centre
        noise = rng.normal(0.0, PIXEL_NOISE_PX, (INPUT_BLOCK, joints, 2))[:n]
        turned = pool[which] @ _rotations(angles).transpose(0, 2, 1)  # (n, J, 3)
        offset = centre * np.array(IMAGE_SIZE) / PSEUDO_FOCAL_PX * depth[:, None]
        cam = turned + np.concatenate([offset, depth[:, None]], axis=1)[:, None]  # (n, J, 3)
        xy[start : start + n] = cam[..., :2] / cam[..., 2:3] * PSEUDO_FOCAL_PX + k[:2, 2] + noise
    return xy, np.ones((count, joints)), np.repeat(k[None], count, axis=0)


def reset_peak_memory(device: str) -> None:
    """Start a new peak: torch's CUDA counter, or the process's peak RSS (Linux: /proc/self/clear_refs)."""
    if torch.device(device).type == "cuda":
        torch.cuda.synchronize(device)
        torch.cuda.reset_peak_memory_stats(device)
        return
    try:
        Path("/proc/self/clear_refs").write_text("5")
    except OSError:
        pass  # not Linux, or not allowed: the peak is then the process's since it started


def peak_memory_mib(device: str) -> tuple[float | None, str]:
    """The peak since `reset_peak_memory` (MiB) and what it measures."""
    if torch.device(device).type == "cuda":
        torch.cuda.synchronize(device)
        return torch.cuda.max_memory_allocated(device) / 2**20, "cuda max_memory_allocated"
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024, "host peak RSS (VmHWM)"
    except OSError:
        pass
    return None, "host peak RSS (not readable here)"


def timed_lift(
    xy: np.ndarray, conf: np.ndarray, k: np.ndarray, prior: Prior, config: LiftConfig, device: str,
    callback: Callable[[LiftProgress], None] | None = None,
) -> tuple[LiftRun, LiftResult]:  # fmt: skip
    """Lift a batch, timing `lift` as `zedo lift` reports it (model loading and input excluded) and
    reading the peak memory it reached."""
    reset_peak_memory(device)
    start = time.perf_counter()
    res = lift(xy, conf, k, prior, config, device=device, callback=callback)
    if torch.device(device).type == "cuda":
        torch.cuda.synchronize(device)
    seconds = time.perf_counter() - start
    peak, kind = peak_memory_mib(device)
    run = LiftRun(len(xy), seconds, len(xy) / seconds, int(res.lifted.sum()), config.chunk_size, peak, kind)
    return run, res


def _status(res: LiftResult) -> np.ndarray:
    assert res.status is not None
    return res.status


def classify_pairs(
    a: np.ndarray, b: np.ndarray, status_a: np.ndarray, status_b: np.ndarray, bones: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per pose of root-relative `a`, `b (N, J, 3)` (NaN where not lifted) with statuses `(N,)`:
    the class (an index into CLASSES) `(N,)`, the largest joint distance (metres, NaN unless both
    lifted) `(N,)`, and which `bones (B, 2)` changed the sign of their depth `(N, B)`."""
    both = (status_a == LIFTED) & (status_b == LIFTED)
    with np.errstate(invalid="ignore"):
        dist = np.where(both, np.linalg.norm(a - b, axis=-1).max(axis=-1), np.nan)  # (N,)
        za = a[:, bones[:, 1], 2] - a[:, bones[:, 0], 2]  # (N, B) the segments' depth components
        zb = b[:, bones[:, 1], 2] - b[:, bones[:, 0], 2]
        flips = both[:, None] & (za * zb < 0) & (np.minimum(np.abs(za), np.abs(zb)) >= FLIP_MIN_DEPTH_M)
    cls = np.full(len(a), CLASSES.index("other_over_10mm"))
    cls[flips.any(1)] = CLASSES.index("depth_flip")
    cls[both & (dist <= AGREE_LOOSE_M)] = CLASSES.index("within_10mm")
    cls[both & (dist <= AGREE_TIGHT_M)] = CLASSES.index("within_1mm")
    cls[~both & (status_a == status_b)] = CLASSES.index("same_refusal")
    cls[status_a != status_b] = CLASSES.index("status_differs")
    return cls, dist, flips


def agreement(reference: LiftResult, other: LiftResult, prior: Prior, largest: int = 10) -> Agreement:
    """How `other` (a device's lift) agrees with `reference` (the CPU's) pose by pose (`classify_pairs`)."""
    bones = np.asarray(prior.skeleton.bones)
    status_a, status_b = _status(reference), _status(other)
    cls, dist, flips = classify_pairs(reference.poses_root_relative, other.poses_root_relative, status_a, status_b,
                                      bones)  # fmt: skip
    counts = {name: int((cls == i).sum()) for i, name in enumerate(CLASSES)}
    n = len(cls)
    tight = counts["within_1mm"] + counts["same_refusal"]
    joints = prior.skeleton.joints
    segments = {f"{joints[p]}-{joints[c]}": int(flips[:, i].sum()) for i, (p, c) in enumerate(bones)}
    order = np.argsort(-np.nan_to_num(dist, nan=-1.0))[:largest]
    worst = []
    for i in order:
        if not dist[i] > 0:  # NaN (not lifted on both) or the same pose: no difference to show
            break
        joint = int(np.linalg.norm(reference.poses_root_relative[i] - other.poses_root_relative[i], axis=-1).argmax())
        worst.append({"pose": int(i), "max_joint_mm": round(float(dist[i]) * 1000, 3), "joint": joints[joint],
                      "class": CLASSES[cls[i]]})  # fmt: skip
    differing = np.flatnonzero(status_a != status_b)[:largest]
    worst += [{"pose": int(i), "class": "status_differs", "cpu": str(status_a[i]), "device": str(status_b[i])}
              for i in differing]  # fmt: skip
    return Agreement(n, int(((status_a == LIFTED) & (status_b == LIFTED)).sum()), tight / max(n, 1),
                     (tight + counts["within_10mm"]) / max(n, 1), counts,
                     {k: v for k, v in segments.items() if v}, worst)  # fmt: skip


def time_fit_prior(data: PoseSet, recipe: Recipe, epochs: int, device: str) -> FitTiming:
    """Train `recipe` on `data` for `epochs` epochs on `device` and time epochs 2.. (the first
    carries the device's start-up); the recipe's full training extrapolated from them."""
    stamps: list[float] = []

    def on_epoch(progress: TrainProgress) -> None:
        if torch.device(device).type == "cuda":
            torch.cuda.synchronize(device)
        stamps.append(time.perf_counter())

    fit_prior(data, with_overrides(recipe, epochs=epochs), device=device, callback=on_epoch)
    per_epoch = (stamps[-1] - stamps[0]) / (len(stamps) - 1)
    steps = -(-len(data.poses) // recipe.training.batch_size)
    return FitTiming(len(data.poses), epochs, steps, per_epoch, recipe.training.epochs,
                     per_epoch * recipe.training.epochs)  # fmt: skip


def run_device_benchmark(
    prior: Prior,
    config: LiftConfig,
    settings: ScaleSettings,
    *,
    device: str,
    preset: str,
    syrip_dir: str | Path | None = None,
    recipe: Recipe | None = None,
    on_stage: Callable[[str, int], Callable[[LiftProgress], None] | None] | None = None,
) -> DeviceReport:
    """Lift `settings.sizes` synthetic poses on `device`, then the first `agreement_poses` again on
    the CPU and compare (on the CPU itself: a repeat run), then time `fit_epochs` of `recipe`'s
    training. `on_stage(label, poses)` gives each lift's progress callback (or None)."""
    on_cpu = torch.device(device).type == "cpu"
    # the same weights on the CPU: the pool is sampled there, and the agreement's reference lift runs there
    cpu_prior = prior if on_cpu else load_prior(prior.path, skeleton=prior.skeleton.name, device="cpu")
    pool = pose_pool(cpu_prior, syrip_dir, settings.seed)
    first = min(settings.agreement_poses, max(settings.sizes))
    xy, conf, k = synthetic_inputs(pool.poses, max(settings.sizes), settings.seed)
    runs: list[LiftRun] = []
    device_first: LiftResult | None = None
    for n in settings.sizes:
        callback = on_stage(f"{device}, {n:,} poses", n) if on_stage else None
        run, res = timed_lift(xy[:n], conf[:n], k[:n], prior, config, device, callback)
        runs.append(run)
        if n >= first and device_first is None and first:
            device_first = _first(res, first)
        del res
    compared = None
    if first:  # on the CPU a repeat run: the same bits expected (docs/lifting.md)
        assert device_first is not None
        callback = on_stage(f"cpu, first {first:,} poses", first) if on_stage else None
        cpu_res = lift(xy[:first], conf[:first], k[:first], cpu_prior, config, device="cpu", callback=callback)
        compared = agreement(cpu_res, device_first, prior)
    fit = None
    if settings.fit_epochs and recipe is not None:
        if on_stage:
            on_stage(f"fit-prior, {settings.fit_epochs} epochs", 0)
        fit = time_fit_prior(pool, recipe, settings.fit_epochs, device)
    return DeviceReport(device, pool.source, preset, runs, compared, fit)


def _first(res: LiftResult, count: int) -> LiftResult:
    """The first `count` poses of a result (what `agreement` reads), copied: the larger batch's
    arrays are not kept alive."""
    status = _status(res)
    return replace(res, poses_camera=res.poses_camera[:count].copy(),
                   poses_root_relative=res.poses_root_relative[:count].copy(),
                   root_translation=res.root_translation[:count].copy(), lifted=res.lifted[:count].copy(),
                   status=status[:count].copy(), reprojection_error_px=res.reprojection_error_px[:count].copy(),
                   observed=res.observed[:count].copy(), hypotheses=None, hypothesis_spread_m=None,
                   uncertainty_m=None)  # fmt: skip
