"""Lifting 2D keypoints to 3D by optimisation under the diffusion prior (ZeDO-i, ALGORITHM.md 3).

1. Initial fit ("IPO"): rotation R0 (unnormalised quaternion) and depth of the prior's template
   pose, with the translation restricted to the root ray, by Adam on the L1 pixel error.
2. Start pose: every observed joint on its own ray at the depth of T0 (a flat pose), rotated
   by R0 about the root.
3. Loop ("OIL"), t from t_start down to t_end: (a) in the last `release_fraction` of the
   iterations, re-solve the root translation T by least squares; (b) move the observed joints
   onto their rays (all the way, as the reference, or the fraction `ray_weight`, less for
   doubted joints and hips: `ray_pull`); (c) where
   enabled, even twin limbs and bone proportions, moving observed joints along their rays;
   (d) one probability-flow step of the prior. After the loop, where enabled, cap twin-limb
   length ratios (`twin_limbs.cap_twin_ratios`).

Vectorised over all poses of a chunk: no per-pose Python loop, no host copies inside the loop,
no per-iteration history. On the CPU, chunks run at once on torch's threads, one intra-op thread
each, so that the result does not depend on the thread count (`chunks.py`). Deviations from the
reference, all documented in docs/benchmarks.md: missing joints are left out of the fit, the
projection and the translation solve (the prior fills them); the output is re-centred on the
skeleton's root.

Presets: `faithful` is the reference's loop (1000 prior steps of delta 1/1000, 500 fit steps).
`fast` (the CLI default) starts at t = 0.2 and takes 20 prior steps of delta 0.03, re-solves the
root translation over the last 15 % of them instead of 5 %, fits R0/T0 in 100 steps, moves
observed joints 0.75 of the way onto their rays (less for joints under 0.6 times their pose's
median confidence, and 0.6 of that for the hips), then takes two rounds of the bone-length terms
(twin limbs, `twin_limbs.py`, and proportions, `proportions.py`) per step, and caps twin ratios at
1.4 after the loop; chosen on held-out SyRIP training folds and confirmed on Test100 (docs/uncertainty.md,
"Speed" and "Plausible skeletons"). Cutting the reference to 100 steps while keeping delta =
1/1000 loses 6 mm: the steps then denoise only a tenth as far.

Instances that cannot be lifted are never reported as lifted: `geometry_status` refuses, before
any work, those whose rays are out of range or coincide; after the loop, a pose that is not
finite, whose translation solve was singular or behind the camera, that has a joint at or behind
the camera, or that misses its 2D joints by far, is marked too. Their poses are NaN and
`LiftResult.status` gives the reason (NOT_LIFTED); the batch's other poses are unaffected.

Warm start (opt-in, `lift(..., start_poses=, start_translation=)`, used by the temporal mode in
`temporal.py`): a pose already close to the answer (the previous video frame's, or a smoothed
one) skips the rotation/depth fit and the flat start, and runs a short loop of `warm_steps`
from the lower noise level `warm_t_start` down to `t_end`, re-solving the root translation in
the last `warm_release_fraction` of it (none by default: the start's translation is kept, as a
smoothed translation is better than one re-solved from one frame's rays). Without a start pose
nothing changes.
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np
import torch

from ..camera.model import CameraModel, undistort_instances
from ..data.skeleton import twin_limbs
from ..errors import ConfigError
from ..prior.sampling import diffusion_scale, probability_flow_step
from ..prior.weights import Prior
from ..rotation import quaternion_to_matrix
from .camera import pixel_rays, project, project_onto_rays, solve_root_translation_ex
from .chunks import BlockNoise, Chunk, deterministic_cuda, lift_workers, plan_chunks, run_chunks
from .config import LiftConfig
from .precision import Network, lift_network
from .proportions import bone_proportion_step, template_fractions
from .reprojection import poor_fit, reprojection_error_px
from .result import LIFTED, LiftResult, hypothesis_spread
from .twin_limbs import cap_twin_ratios, twin_limb_step

# A pinhole image of a joint more than ~87 degrees off the optical axis is not a real camera's:
# such a ray means a wrong focal length or principal point (or wrong coordinates).
MAX_RAY_SLOPE = 20.0
# Observed joints whose rays all lie within this angle (radians, ~ a fifth of a pixel at f = 2000 px)
# of their mean determine no depth: the translation solve is singular.
MIN_RAY_SPREAD = 1e-4
# The nearest a lifted joint may be to the camera (metres); nearer, or behind, is a failed fit.
MIN_JOINT_DEPTH_M = 0.01

# A lifted bone longer than this many times the same bone of the prior's template pose is not a
# body's: a safety net for a loop that diverged (default settings on SyRIP's 1400 real poses:
# at most 2.7, from one FiDIP detection; diverged loops: 11-13).
MAX_BONE_RATIO = 4.0
HIP_JOINTS = ("left_hip", "right_hip")  # the joints `LiftConfig.hip_ray_factor` applies to
# Why an instance is not lifted (`LiftResult.status`; "lifted" otherwise). Its 3D is NaN.
NOT_LIFTED = {
    "too_few_observed_joints": "fewer observed joints than the lifting needs",
    "ray_out_of_range": "a joint's pixel or camera ray is not finite or is more than "
    f"{np.degrees(np.arctan(MAX_RAY_SLOPE)):.0f} degrees off the optical axis (check the coordinates, the focal "
    "length and the principal point)",
    "degenerate_geometry": "the observed joints' rays coincide (e.g. every joint at one pixel), so depth and "
    "translation are undetermined",
    "non_finite_result": "the optimisation produced a non-finite pose",
    "behind_camera": "the best fit to the rays put the person at or behind the camera (the 2D pose does not fit "
    "the prior, e.g. a tiny, partial or low-confidence detection)",
    "poor_fit": "the lifted pose misses its observed 2D joints by more than half the 2D pose's radius on average "
    "(the 2D pose does not fit the prior, e.g. a tiny, partial or low-confidence detection)",
    "implausible_skeleton": f"a lifted bone is more than {MAX_BONE_RATIO:g} times as long as in the prior's template "
    "(the loop diverged, e.g. with very few --steps)",
}


@dataclass(frozen=True)
class LiftProgress:
    done: int  # optimisation steps done over all chunks
    total: int


def observed_mask(xy: np.ndarray, confidence: np.ndarray, min_confidence: float) -> np.ndarray:
    """Joints usable as constraints: finite pixels and a confidence above 0 and the threshold."""
    return np.isfinite(xy).all(-1) & (confidence > 0) & (confidence >= min_confidence)


def _root_pixels(xy: torch.Tensor, w: torch.Tensor, root_idx: list[int]) -> torch.Tensor:
    """2D root `(B, 2)`: the mean of the root joints when all are observed, else the mean of
    the observed joints (the reference has no missing joints to handle)."""
    root_ok = w[:, root_idx].all(dim=1, keepdim=True)
    root_mean = xy[:, root_idx].mean(dim=1)
    obs_mean = (xy * w[..., None]).sum(1) / w.sum(1, keepdim=True)
    return torch.where(root_ok, root_mean, obs_mean)


class _Adam:
    """Adam (Kingma & Ba 2015; betas 0.9 / 0.999, eps 1e-8) for the two tensors of the rotation fit.

    Written out instead of `torch.optim.Adam` because importing torch.optim loads torch's
    compiler stack (about 0.8 s of start-up for every `zedo lift`). The operations and their
    order are those of torch's single-tensor CPU Adam, so results are the same to the bit
    (tests/lifting/test_lifting.py compares them).
    """

    def __init__(self, params: list[torch.Tensor], lr: float, betas: tuple[float, float] = (0.9, 0.999),
                 eps: float = 1e-8) -> None:  # fmt: skip
        self.params, self.lr, self.betas, self.eps, self.steps = params, lr, betas, eps, 0
        self.m = [torch.zeros_like(p) for p in params]
        self.v = [torch.zeros_like(p) for p in params]

    @torch.no_grad()
    def step(self) -> None:
        beta1, beta2 = self.betas
        self.steps += 1
        step_size = self.lr / (1 - beta1**self.steps)
        correction2_sqrt = (1 - beta2**self.steps) ** 0.5
        for p, m, v in zip(self.params, self.m, self.v, strict=True):
            g = p.grad
            m.lerp_(g, 1 - beta1)
            v.mul_(beta2).addcmul_(g, g, value=1 - beta2)
            p.addcdiv_(m, (v.sqrt() / correction2_sqrt).add_(self.eps), value=-step_size)


@dataclass(frozen=True)
class _ChunkResult:
    pose: torch.Tensor  # (B, K, J, 3) root-relative, K hypotheses
    translation: torch.Tensor  # (B, K, 3)
    singular: torch.Tensor  # (B, K) bool: a translation solve was singular
    flipped: torch.Tensor  # (B, K) bool: a least-squares translation was behind the camera

    def per_instance(self, count: int) -> _ChunkResult:
        """The loop's rows (B * K, ...) regrouped as (B, K, ...)."""

        def group(t: torch.Tensor) -> torch.Tensor:
            return t.reshape(-1, count, *t.shape[1:])

        return _ChunkResult(group(self.pose), group(self.translation), group(self.singular), group(self.flipped))


def fit_rotation_depth(
    template: torch.Tensor, xy: torch.Tensor, k: torch.Tensor, w: torch.Tensor,
    root_dir: torch.Tensor, cfg: LiftConfig,
) -> tuple[torch.Tensor, torch.Tensor]:  # fmt: skip
    """R0 `(B, 3, 3)` and T0 `(B, 3)` fitting `template (J, 3)` to pixels `xy (B, J, 2)`.

    T0 = clamp(s) * root_dir: only the distance along the root ray is free. The loss is the
    L1 pixel error averaged over observed joints and both coordinates, summed over poses (so
    each pose's fit does not depend on the others; Adam is per element).
    """
    batch = xy.shape[0]
    q = torch.zeros(batch, 4, dtype=xy.dtype, device=xy.device)
    q[:, 0] = 1.0
    s = torch.ones(batch, 1, dtype=xy.dtype, device=xy.device)
    q.requires_grad_(True)
    s.requires_grad_(True)
    opt = _Adam([q, s], lr=cfg.init_lr)
    count = 2.0 * w.sum(1)
    with torch.enable_grad():
        for _ in range(cfg.init_steps):
            rot = quaternion_to_matrix(q)
            cam = template @ rot.transpose(1, 2) + (s.clamp(cfg.scale_min, cfg.scale_max) * root_dir)[:, None]
            err = (project(cam, k) - xy).abs().sum(-1)  # (B, J)
            loss = ((err * w).sum(1) / count).sum()
            q.grad = s.grad = None
            loss.backward()
            opt.step()
    with torch.no_grad():
        return quaternion_to_matrix(q), s.clamp(cfg.scale_min, cfg.scale_max) * root_dir


@torch.no_grad()
def _lift_chunk(
    prior: Prior, net: Network, xy: torch.Tensor, k: torch.Tensor, w: torch.Tensor, pull: torch.Tensor | None,
    cfg: LiftConfig, tick: Callable[[int], None], draws: BlockNoise | None,
) -> _ChunkResult:  # fmt: skip
    """Root-relative poses X `(B, K, J, 3)` and translations T `(B, K, 3)` of one chunk's K
    hypotheses (`cfg.hypotheses`; the perturbations drawn from `draws`, given when K > 1); `pull
    (B, J)` from `ray_pull`."""
    skel = prior.skeleton
    obs = w > 0
    rays = pixel_rays(xy, k)  # (B, J, 3), z = 1
    unit = rays / rays.norm(dim=-1, keepdim=True)
    root_ray = pixel_rays(_root_pixels(xy, w, skel.root_indices)[:, None], k)[:, 0]
    root_dir = cfg.init_depth_m * root_ray / root_ray.norm(dim=-1, keepdim=True)
    template = prior.template.to(xy)
    rot0, trans = fit_rotation_depth(template, xy, k, w, root_dir, cfg)
    tick(cfg.init_steps)
    # The reference starts from the flat pose on the rays at the depth of T0, rotated by R0
    # (ALGORITHM.md 3.4). Missing joints start at the template's joint instead.
    flat = torch.where(obs[..., None], trans[:, None, 2:3] * rays - trans[:, None], template)
    x = flat @ rot0.transpose(1, 2)
    ts = torch.linspace(cfg.t_start, cfg.t_end, cfg.steps, dtype=xy.dtype, device=xy.device)
    release = round(cfg.steps * (1.0 - cfg.release_fraction))
    count = cfg.hypotheses
    noise = None
    if count > 1:  # hypothesis 0 of each instance is the deterministic lift, the others are perturbed
        assert draws is not None
        x, trans, rays, unit, w = (t.repeat_interleave(count, 0) for t in (x, trans, rays, unit, w))
        pull = None if pull is None else pull.repeat_interleave(count, 0)
        other = (torch.arange(x.shape[0], device=x.device) % count != 0).to(x.dtype)[:, None, None]
        jitter = draws.randn(x.shape[1:2], x.dtype)[..., None]
        x = x + other * cfg.start_jitter_m * torch.where(w[..., None] > 0, jitter * unit, 0.0)
        noise = other * cfg.hypothesis_noise
    out = _prior_loop(prior, net, x, trans, rays, unit, w, pull, ts, release, cfg.delta, cfg, tick, noise, draws)
    return out.per_instance(count)


@torch.no_grad()
def _warm_chunk(
    prior: Prior, net: Network, xy: torch.Tensor, k: torch.Tensor, w: torch.Tensor, pull: torch.Tensor | None,
    x0: torch.Tensor, t0: torch.Tensor, cfg: LiftConfig, tick: Callable[[int], None],
) -> _ChunkResult:  # fmt: skip
    """Like `_lift_chunk`, from start poses `x0 (B, J, 3)` and translations `t0 (B, 3)`: no fit,
    a short loop from `warm_t_start`; one hypothesis."""
    rays = pixel_rays(xy, k)
    unit = rays / rays.norm(dim=-1, keepdim=True)
    ts = torch.linspace(cfg.warm_t_start, cfg.t_end, cfg.warm_steps, dtype=xy.dtype, device=xy.device)
    release = round(cfg.warm_steps * (1.0 - cfg.warm_release_fraction))
    return _prior_loop(prior, net, x0, t0, rays, unit, w, pull, ts, release, cfg.warm_delta, cfg, tick).per_instance(1)


def _prior_loop(
    prior: Prior, net: Network, x: torch.Tensor, trans: torch.Tensor, rays: torch.Tensor, unit: torch.Tensor,
    w: torch.Tensor, pull: torch.Tensor | None, ts: torch.Tensor, release: int, delta: float, cfg: LiftConfig,
    tick: Callable[[int], None],
    noise: torch.Tensor | None = None, draws: BlockNoise | None = None,
) -> _ChunkResult:  # fmt: skip
    """The loop (ALGORITHM.md 3.5) over the noise levels `ts`: translation re-solved from
    iteration `release` on, observed joints moved onto their rays (all the way, or the fraction
    `pull (B, J)` of it), twin limbs evened (`cfg.twin_rate`) and bone proportions kept
    (`cfg.proportion_rate`), one prior step; rows with a `noise (B, 1, 1)` factor above 0 also get
    that fraction of the reverse SDE's noise (drawn from `draws`). After the loop, twin ratios
    over `cfg.twin_ratio_cap` are capped.

    A pose whose translation solve is singular keeps its previous translation and is reported;
    so is one whose least-squares translation was behind the camera at any solve (the
    reference negates it; that T does not keep the joints on their rays, and the following
    projections onto the rays then drive the pose towards, and behind, the camera).
    """
    obs = w > 0
    pairs = twin_limbs(prior.skeleton)
    bones = torch.as_tensor(prior.skeleton.bones, device=x.device).reshape(-1, 2)
    fractions = template_fractions(prior.template, prior.skeleton).to(device=x.device, dtype=x.dtype)
    steps = len(ts)
    singular = torch.zeros(x.shape[0], dtype=torch.bool, device=x.device)
    flipped = torch.zeros_like(singular)
    every, reported = max(1, steps // 20), 0  # about 20 progress reports per chunk
    for i in range(steps):
        if i >= release:
            solved = solve_root_translation_ex(x, rays, w, fallback=trans)
            trans, singular, flipped = solved.translation, singular | solved.singular, flipped | solved.flipped
        on_rays = project_onto_rays(x + trans[:, None], unit) - trans[:, None]
        if pull is not None:  # part of the way: the prior may keep a joint off a ray it disagrees with
            on_rays = torch.lerp(x, on_rays, pull[..., None])
        x = torch.where(obs[..., None], on_rays, x)
        for _ in range(cfg.length_iterations):
            x = twin_limb_step(x, unit, obs, pairs, cfg.twin_rate)
            x = bone_proportion_step(x, unit, obs, bones, fractions, cfg.proportion_rate)
        eps = net(x, ts[i])
        x = probability_flow_step(x, eps, ts[i], prior.sde, delta, cfg.flow)
        if noise is not None:
            assert draws is not None
            z = draws.randn(x.shape[1:], x.dtype)
            x = x + noise * diffusion_scale(ts[i], prior.sde, delta) * z
        if (i + 1) % every == 0 or i + 1 == steps:
            tick(i + 1 - reported)
            reported = i + 1
    x = cap_twin_ratios(x, unit, obs, pairs, cfg.twin_ratio_cap)
    return _ChunkResult(x, trans, singular, flipped)


def lift(
    xy: np.ndarray,
    confidence: np.ndarray,
    intrinsics: np.ndarray,
    prior: Prior,
    config: LiftConfig = LiftConfig(),
    *,
    min_confidence: float = 0.0,
    device: str = "cpu",
    callback: Callable[[LiftProgress], None] | None = None,
    start_poses: np.ndarray | None = None,
    start_translation: np.ndarray | None = None,
    seed: int = 0,
    cameras: Sequence[CameraModel | None] | None = None,
    threads: int | None = None,
) -> LiftResult:
    """Lift pixels `xy (N, J, 2)` with confidences `(N, J)` and intrinsics `(N, 3, 3)` to 3D.

    Lens distortion (optional): `cameras`, one `CameraModel` per instance (None: no lens; as
    `camera.resolve_cameras` gives them). Pixels of a camera with distortion are undistorted
    (OpenCV) and lifted through the pinhole camera of the same K; their reprojection errors are
    measured in the original, distorted image (the lifted joints projected through the lens).
    Without distortion nothing changes and nothing is spent.

    The joints must be in the prior's joint set. Missing joints (NaN, confidence 0 or below
    `min_confidence`) are not used as constraints; the prior fills them.

    Warm start (optional, both or neither): `start_poses (N, J, 3)` root-relative metres in the
    camera frame and `start_translation (N, 3)` their root points. An instance whose start is
    finite skips the rotation/depth fit and runs the short loop of `config.warm_steps` from
    `config.warm_t_start`; one with a NaN start is lifted from scratch as usual.

    With `config.hypotheses` K > 1, each instance is lifted K times in one batch (hypothesis 0 as
    with K = 1, the others perturbed from `seed`: same seed, same output) and the reported pose
    is their `config.aggregate`, over the hypotheses that were lifted; the status is hypothesis 0's.

    On the CPU, chunks of the batch run on `threads` threads at once (default: torch's thread count),
    each with one intra-op thread: the result is the same to the bit for any thread count and
    batch size (`chunks.py`). On CUDA, torch's deterministic settings are switched on
    (`chunks.deterministic_cuda`).
    """
    start = time.perf_counter()
    n, joints = xy.shape[:2]
    if joints != prior.skeleton.num_joints:
        raise ConfigError(f"keypoints have {joints} joints, the prior's skeleton {prior.skeleton.num_joints}")
    obs = observed_mask(xy, confidence, min_confidence)
    pull = ray_pull(confidence, obs, config, prior.skeleton.joints)
    seen, xy = xy, undistort_instances(xy, cameras)  # the input's pixels, and where a pinhole camera sees them
    status = geometry_status(xy, intrinsics, obs, config.min_observed)
    todo_all = status == LIFTED
    warm = _warm_mask(start_poses, start_translation, n, joints) & todo_all
    todo, todo_warm = np.flatnonzero(todo_all & ~warm), np.flatnonzero(warm)
    count = config.hypotheses
    workers = lift_workers(device, threads)
    if torch.device(device).type == "cuda":
        deterministic_cuda()
    chunks = plan_chunks(len(todo), count, config.chunk_size, workers)  # chunk_size counts the loop's rows
    warm_chunks = plan_chunks(len(todo_warm), 1, config.chunk_size, workers)
    net = lift_network(prior.model, config, device)  # float32, or bfloat16 products (`precision.py`)
    total = len(chunks) * (config.init_steps + config.steps) + len(warm_chunks) * config.warm_steps
    done = 0

    def on_steps(steps: int) -> None:  # called under run_chunks' lock
        nonlocal done
        done += steps
        if callback is not None:
            callback(LiftProgress(done, total))

    batch = _Batch(prior, net, config, device, seed, xy, intrinsics, obs, pull, todo, todo_warm, start_poses,
                   start_translation, np.full((n, count, joints, 3), np.nan), np.zeros((n, count), dtype=bool),
                   np.zeros((n, count), dtype=bool))  # fmt: skip
    run_chunks(chunks, batch.cold, workers, device, on_steps)
    run_chunks(warm_chunks, batch.warm, workers, device, on_steps)
    raw = _Lifted(batch.cam, batch.singular, batch.flipped, status, seen, obs, intrinsics, cameras)
    return replace(_assemble(raw, prior, config), seconds=time.perf_counter() - start)


@dataclass
class _Batch:
    """One `lift` call's instances, lifted chunk by chunk into `cam (N, K, J, 3)` and its flags `(N, K)`: cold
    (`todo`) or warm-started (`todo_warm`) from `start_poses` / `start_translation`."""

    prior: Prior
    net: Network
    config: LiftConfig
    device: str
    seed: int
    xy: np.ndarray
    intrinsics: np.ndarray
    obs: np.ndarray
    pull: np.ndarray | None
    todo: np.ndarray
    todo_warm: np.ndarray
    start_poses: np.ndarray | None
    start_translation: np.ndarray | None
    cam: np.ndarray
    singular: np.ndarray
    flipped: np.ndarray

    def tensor(self, a: np.ndarray) -> torch.Tensor:
        return torch.as_tensor(a, dtype=torch.float32, device=self.device)

    def inputs(self, idx: np.ndarray) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor, torch.Tensor | None]:
        """The pixels, intrinsics, observed joints and ray pulls of the instances `idx`, as tensors."""
        pull = None if self.pull is None else self.tensor(self.pull[idx])
        return (self.tensor(np.nan_to_num(self.xy[idx])), self.tensor(self.intrinsics[idx]), self.tensor(self.obs[idx]),
                pull)  # fmt: skip

    def store(self, idx: np.ndarray, out: _ChunkResult) -> None:
        hyp, real = out.pose.shape[1], len(idx)  # the rows after `real` are the chunk's padding
        self.cam[idx, :hyp] = (out.pose[:real] + out.translation[:real, :, None]).double().cpu().numpy()
        self.singular[idx, :hyp] = out.singular[:real].cpu().numpy()
        self.flipped[idx, :hyp] = out.flipped[:real].cpu().numpy()

    def cold(self, chunk: Chunk, tick: Callable[[int], None]) -> None:
        idx = self.todo[chunk.positions()]
        count = self.config.hypotheses
        draws = BlockNoise(self.seed, chunk, count, self.device) if count > 1 else None
        self.store(self.todo[chunk.start : chunk.stop],
                   _lift_chunk(self.prior, self.net, *self.inputs(idx), self.config, tick, draws))  # fmt: skip

    def warm(self, chunk: Chunk, tick: Callable[[int], None]) -> None:
        assert self.start_poses is not None and self.start_translation is not None
        idx = self.todo_warm[chunk.positions()]
        starts = self.tensor(self.start_poses[idx]), self.tensor(self.start_translation[idx])
        self.store(self.todo_warm[chunk.start : chunk.stop],
                   _warm_chunk(self.prior, self.net, *self.inputs(idx), *starts, self.config, tick))  # fmt: skip


@dataclass(frozen=True)
class _Lifted:
    """What the chunks gave: poses `(N, K, J, 3)` of every hypothesis, their singular and flipped flags `(N, K)`,
    the geometry status `(N,)`, and the input's pixels, observed joints, intrinsics and lenses."""

    cam: np.ndarray
    singular: np.ndarray
    flipped: np.ndarray
    status: np.ndarray
    seen: np.ndarray
    obs: np.ndarray
    intrinsics: np.ndarray
    cameras: Sequence[CameraModel | None] | None


def _assemble(raw: _Lifted, prior: Prior, config: LiftConfig) -> LiftResult:
    """The result of `lift` from its chunks: the hypotheses' aggregate, reprojection errors, statuses, the root."""
    n, count, joints = raw.cam.shape[:3]
    cam, hypotheses, aggregate = raw.cam, None, None
    if count > 1:
        bones = bone_ratio(cam.reshape(n * count, joints, 3), prior).reshape(n, count)
        hypotheses = _usable_hypotheses(cam, raw.singular, raw.flipped, bones)
        aggregate = _aggregate(hypotheses, config.aggregate)
    cam, singular, flipped = cam[:, 0], raw.singular[:, 0], raw.flipped[:, 0]
    if aggregate is not None:
        cam = np.where(np.isfinite(aggregate).all(axis=(1, 2))[:, None, None], aggregate, cam)
    reproj = reprojection_error_px(cam, raw.seen, raw.intrinsics, raw.obs, raw.cameras)
    status = _result_status(raw.status, cam, singular, flipped, raw.seen, raw.obs, reproj, bone_ratio(cam, prior))
    lifted = status == LIFTED
    cam[~lifted], reproj[~lifted] = np.nan, np.nan
    root = cam[:, prior.skeleton.root_indices].mean(axis=1)
    spread = None
    if hypotheses is not None:
        hypotheses[~lifted] = np.nan
        hypotheses = hypotheses - hypotheses[:, :, prior.skeleton.root_indices].mean(axis=2, keepdims=True)
        spread = hypothesis_spread(hypotheses, cam - root[:, None])
    return LiftResult(cam, cam - root[:, None], root, reproj, raw.obs, lifted, config, 0.0, status, hypotheses,
                      hypothesis_spread_m=spread)  # fmt: skip


def ray_pull(
    confidence: np.ndarray, observed: np.ndarray, cfg: LiftConfig, joints: tuple[str, ...]
) -> np.ndarray | None:
    """The fraction of the way to its ray `(N, J)` each joint moves before every prior step:
    `cfg.ray_weight`, times confidence / (`cfg.ray_confidence_ratio` x the median confidence of the
    pose's `observed (N, J)` joints) where that is below 1, times `cfg.hip_ray_factor` for the
    `joints` named left_hip and right_hip. None: all the way for every joint (the reference)."""
    if cfg.ray_weight == 1 and cfg.ray_confidence_ratio == 0 and cfg.hip_ray_factor == 1:
        return None
    pull = np.full(confidence.shape, cfg.ray_weight)
    pull[:, [i for i, name in enumerate(joints) if name in HIP_JOINTS]] *= cfg.hip_ray_factor
    if cfg.ray_confidence_ratio > 0:
        conf = np.where(observed, np.nan_to_num(confidence), np.nan)
        with warnings.catch_warnings():  # a pose with no observed joint is not lifted; its median is NaN
            warnings.simplefilter("ignore", RuntimeWarning)
            median = np.nanmedian(conf, axis=1, keepdims=True)
        scale = cfg.ray_confidence_ratio * np.where(np.isfinite(median) & (median > 0), median, 1.0)
        pull *= np.clip(np.nan_to_num(conf) / scale, 0.0, 1.0)
    return pull


def _usable_hypotheses(cam: np.ndarray, singular: np.ndarray, flipped: np.ndarray, bones: np.ndarray) -> np.ndarray:
    """Camera-frame hypotheses `cam (N, K, J, 3)` with those that failed (not finite, a singular or
    behind-camera translation, a joint at or behind the camera, a `bones (N, K)` ratio over
    MAX_BONE_RATIO) set to NaN."""
    with np.errstate(invalid="ignore"):
        good = np.isfinite(cam).all(axis=(2, 3)) & ~singular & ~flipped & (cam[..., 2] >= MIN_JOINT_DEPTH_M).all(-1)
        good &= bones <= MAX_BONE_RATIO
    return np.where(good[..., None, None], cam, np.nan)


def _aggregate(hypotheses: np.ndarray, how: str) -> np.ndarray:
    """The reported pose `(N, J, 3)` from hypotheses `(N, K, J, 3)` (NaN: unusable): their joint-wise
    mean or median, or hypothesis 0 ("first")."""
    if how == "first":
        return hypotheses[:, 0].copy()
    with warnings.catch_warnings():  # an instance with no usable hypothesis gives NaN, handled by the caller
        warnings.simplefilter("ignore", RuntimeWarning)
        return np.nanmean(hypotheses, axis=1) if how == "mean" else np.nanmedian(hypotheses, axis=1)


def geometry_status(xy: np.ndarray, intrinsics: np.ndarray, observed: np.ndarray, min_observed: int) -> np.ndarray:
    """Whether each instance can be lifted at all, before any work: `(N,)` "lifted" or the
    reason (a key of NOT_LIFTED) from its pixels `xy (N, J, 2)`, intrinsics `(N, 3, 3)` and
    observed joints `(N, J)`. Computed in float64, so that nothing overflows here."""
    with np.errstate(all="ignore"):  # inf and NaN are what this looks for
        k = np.asarray(intrinsics, dtype=np.float64)
        focal, centre = k[:, [0, 1], [0, 1]], k[:, [0, 1], [2, 2]]  # (N, 2)
        rays = (np.asarray(xy, dtype=np.float64) - centre[:, None]) / focal[:, None]  # (N, J, 2), z = 1
        good_ray = np.isfinite(rays).all(-1) & (np.abs(rays) <= MAX_RAY_SLOPE).all(-1)
        good_k = np.isfinite(k).all(axis=(1, 2)) & (focal > 0).all(1)
        count = observed.sum(1)
        obs_rays = np.where(observed[..., None] & good_ray[..., None], rays, 0.0)
        mean = obs_rays.sum(1) / np.maximum(count, 1)[:, None]  # (N, 2)
        dev = np.where(observed, ((obs_rays - mean[:, None]) ** 2).sum(-1), 0.0)
        spread = np.sqrt(dev.sum(1) / np.maximum(count, 1))  # RMS angle about the mean ray
    status = np.full(len(xy), LIFTED, dtype=object)  # object: reasons are longer than "lifted"
    status[spread < MIN_RAY_SPREAD] = "degenerate_geometry"
    status[~good_k | (observed & ~good_ray).any(1)] = "ray_out_of_range"
    status[count < min_observed] = "too_few_observed_joints"
    return status


def bone_ratio(cam: np.ndarray, prior: Prior) -> np.ndarray:
    """Per pose `cam (N, J, 3)`, the largest ratio of a bone's length to its length in the
    prior's template `(N,)` (NaN for a pose that is not finite)."""
    bones = np.asarray(prior.skeleton.bones)
    template = prior.template.detach().cpu().numpy().astype(np.float64)
    reference = np.linalg.norm(template[bones[:, 0]] - template[bones[:, 1]], axis=-1)
    lengths = np.linalg.norm(cam[:, bones[:, 0]] - cam[:, bones[:, 1]], axis=-1)
    with np.errstate(all="ignore"):
        return (lengths / np.maximum(reference, 1e-6)).max(axis=1)


def _result_status(
    status: np.ndarray, cam: np.ndarray, singular: np.ndarray, flipped: np.ndarray, xy: np.ndarray,
    observed: np.ndarray, reproj: np.ndarray, bones: np.ndarray,
) -> np.ndarray:  # fmt: skip
    """`status (N,)` after lifting: a lifted pose `cam (N, J, 3)` that is not finite, whose
    translation solve was `singular (N,)` or behind the camera (`flipped (N,)`), that has a
    joint at or behind the camera, whose reprojection errors `reproj (N, J)` px miss its
    observed pixels `xy (N, J, 2)` by far, or whose `bones (N,)` ratio (`bone_ratio`) exceeds
    MAX_BONE_RATIO, is marked so (in this order of precedence)."""
    with np.errstate(all="ignore"):  # the poses of failed instances may hold inf and NaN
        finite = np.isfinite(cam).all(axis=(1, 2))
        near = (cam[..., 2] < MIN_JOINT_DEPTH_M).any(1)
        implausible = ~(bones <= MAX_BONE_RATIO)
    poor = poor_fit(xy, observed, reproj)
    out = status.copy()
    todo = status == LIFTED
    for failed, reason in ((~finite, "non_finite_result"), (singular, "degenerate_geometry"),
                           (flipped | near, "behind_camera"), (poor, "poor_fit"),
                           (implausible, "implausible_skeleton")):  # fmt: skip
        out[todo & failed] = reason
        todo &= ~failed
    return out


def _warm_mask(poses: np.ndarray | None, trans: np.ndarray | None, n: int, joints: int) -> np.ndarray:
    """Instances `(N,)` with a usable (finite) start pose and translation."""
    if poses is None and trans is None:
        return np.zeros(n, dtype=bool)
    if poses is None or trans is None:
        raise ConfigError("a warm start needs both start_poses and start_translation")
    if poses.shape != (n, joints, 3) or trans.shape != (n, 3):
        raise ConfigError(f"start poses {poses.shape} / translations {trans.shape} do not match {n} instances "
                          f"of {joints} joints")  # fmt: skip
    return np.isfinite(poses).all(axis=(1, 2)) & np.isfinite(trans).all(axis=1)
