"""A tried and rejected remedy for the knee's clip mean angle (docs/movement.md, "What limits the knee's mean
angle"): a motion model across frames that makes each limb segment keep its depth sign while it points
clearly along the camera's axis.

A segment's true depth sign can only change when the segment passes through the image plane. Its |unit z|
needs no sign: from the lifted segment's image-plane length l and the clip's median 3D length L of that
segment, sqrt(1 - (l / L)^2). Per clip, side and segment (thigh, shank, upper arm, forearm; proximal first),
the frames where that estimate exceeds `tau` form runs; within a run, the lifted depth signs vote (the sum of
the lifted z, or with `count` one vote a frame), and the frames on the losing side (`minority`; `weak` also
those whose |z| is under half the estimate's, as a smoothed flip leaves them; `all` every frame of the run)
get the winning sign with the estimated |z|, their distal joints moved with them. The clips are
features_3d_accuracy.py's table clips (16 clips of 5 s a fold, `--interpolation` motion), lifted by each fold
prior `fold<k>.safetensors` in `--folds` (default preset, `--temporal smooth`). It prints, per variant:

- the mean absolute error of the elbow and knee `3d_mean_angle` and `3d_median_vel_angle` against the truth
  and its ratio to the published 2D features' error (the target: at most 0.5);
- of the frames where the true and the lifted segment point clearly along the depth axis (|unit z| > 0.3),
  the share on the wrong side, before and after the vote.

Test100 and SyRIP's synthetic rows are never read.

    OMP_NUM_THREADS=2 .venv/bin/python experiments/depth_sign_vote.py --syrip-dir ../shared/data/syrip \
        --folds FOLDS [--interpolation segments]
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root
from benchmarks.accuracy.limb_depth_flips import CLEAR_DEPTH, SEGMENTS, depth_direction, flipped
from benchmarks.lib.folds import fold_clip_args, fold_priors
from benchmarks.lib.settings import CLIP_SETTINGS
from zedo_cli.analysis.clip.features_3d import features_3d
from zedo_cli.analysis.clip.published_features import published_features
from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.evaluation.clips.eased import IMAGE_H, IMAGE_W, make_sequences

SKELETON = get_skeleton("syrip12")
JOINT = {name: i for i, name in enumerate(SKELETON.joints)}
CHAINS = (("hip", "knee", "ankle"), ("shoulder", "elbow", "wrist"))
FEATURES = ("mean_angle", "median_vel_angle")
PARTS = ("Elbow", "Knee")


@dataclass(frozen=True)
class Vote:
    tau: float = 0.3  # the estimated |unit z| above which a frame belongs to a run
    fix: str = "minority"  # which frames of a run take the winning sign: minority, weak or all
    ballot: str = "depth"  # depth: the lifted z's sum decides; count: one vote a frame


VARIANTS = {
    "as lifted": None,
    "minority, tau 0.2": Vote(tau=0.2),
    "minority, tau 0.3": Vote(),
    "minority, tau 0.4": Vote(tau=0.4),
    "weak, tau 0.3": Vote(fix="weak"),
    "all, tau 0.3": Vote(fix="all"),
    "count, tau 0.3": Vote(ballot="count"),
}


def runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """(start, stop) of each run of True in `mask (N,)`."""
    edges = np.diff(np.concatenate([[0], mask.astype(int), [0]]))
    return list(zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1), strict=True))


def sign_free_depth(vec: np.ndarray) -> tuple[np.ndarray, float]:
    """A segment's |unit z| `(N,)` without its sign, from the image-plane length of each of its vectors
    `vec (N, 3)` against their median 3D length (NaN where a frame is not lifted), and that length."""
    length = float(np.nanmedian(np.linalg.norm(vec, axis=-1)))
    with np.errstate(invalid="ignore"):
        return np.sqrt(np.clip(1.0 - (np.linalg.norm(vec[:, :2], axis=-1) / length) ** 2, 0.0, 1.0)), length


def vote(poses: np.ndarray, rule: Vote) -> np.ndarray:
    """`poses (N, J, 3)` of one clip (camera axes, z depth) with each segment's depth sign voted per run."""
    out = poses.copy()
    for side in ("left", "right"):
        for chain in CHAINS:
            ids = [JOINT[f"{side}_{name}"] for name in chain]
            for s in range(len(ids) - 1):
                vec = out[:, ids[s + 1]] - out[:, ids[s]]
                z_size, length = sign_free_depth(vec)
                for start, stop in runs(np.isfinite(z_size) & (z_size > rule.tau)):
                    z = vec[start:stop, 2]
                    winner = np.sign(np.sum(np.sign(z) if rule.ballot == "count" else z))
                    if winner == 0:
                        continue
                    target = winner * length * z_size[start:stop]
                    fix = np.sign(z) != winner
                    if rule.fix == "weak":
                        fix |= np.abs(z) < 0.5 * np.abs(target)
                    elif rule.fix == "all":
                        fix[:] = True
                    for distal in ids[s + 1 :]:
                        out[start:stop, distal, 2] += np.where(fix, target - z, 0.0)
    return out


def wrong_side(truth: np.ndarray, lifted: np.ndarray) -> tuple[int, int]:
    """Frames x segments x sides where both point clearly along the depth axis, and those on opposite sides."""
    clear = wrong = 0
    for side in ("left", "right"):
        for segment in SEGMENTS:
            tz, lz = depth_direction(truth, side, segment), depth_direction(lifted, side, segment)
            clear += int(((np.abs(tz) > CLEAR_DEPTH) & (np.abs(lz) > CLEAR_DEPTH)).sum())
            wrong += int(flipped(tz, lz).sum())
    return clear, wrong


def main() -> int:
    args = fold_clip_args(__doc__, interpolation="segments")

    from zedo_cli.lifting.config import DEFAULT_PRESET, get_preset
    from zedo_cli.lifting.temporal import lift_sequence

    cfg = get_preset(DEFAULT_PRESET)
    fps = float(CLIP_SETTINGS["fps"])
    size = np.array([IMAGE_W, IMAGE_H], dtype=float)
    errors: dict[str, dict[tuple[str, str], list[float]]] = {name: {} for name in [*VARIANTS, "2D"]}
    signs = {name: [0, 0] for name in VARIANTS}
    for k, prior, truth, _ in fold_priors(args.folds, "", args.syrip_dir):
        torch.manual_seed(k)
        clips = make_sequences(truth.poses, np.random.default_rng(100 + k), **CLIP_SETTINGS,
                               interpolation=args.interpolation)  # fmt: skip
        res = lift_sequence(clips["xy"], clips["conf"], clips["k"], prior, cfg, mode="smooth", tracks=clips["tracks"])
        lifted = np.where(res.lifted[:, None, None], res.poses_root_relative, np.nan)
        for track in np.unique(clips["tracks"]):
            at = clips["tracks"] == track
            true = features_3d(clips["rel"][at], SKELETON, fps).values
            flat = published_features(clips["xy"][at], SKELETON, fps, size).values
            for name, rule in VARIANTS.items():
                poses = lifted[at] if rule is None else vote(lifted[at], rule)
                clear, wrong = wrong_side(clips["rel"][at], poses)
                signs[name][0] += clear
                signs[name][1] += wrong
                ours = features_3d(poses, SKELETON, fps).values
                for f in FEATURES:
                    for side in "LR":
                        for part in PARTS:
                            t = true[f"3d_{f}_{side}{part}"]
                            errors[name].setdefault((f, part), []).append(abs(ours[f"3d_{f}_{side}{part}"] - t))
                            if rule is None:
                                errors["2D"].setdefault((f, part), []).append(abs(flat[f"{f}_{side}{part}"] - t))
        print(f"fold {k}: {len(np.unique(clips['tracks']))} clips lifted", file=sys.stderr, flush=True)

    print(f"{args.interpolation} clips; MAE against the 3D truth (elbow, knee, both) and both / published 2D:")
    for f in FEATURES:
        flat = errors["2D"]
        both_2d = np.mean(flat[(f, "Elbow")] + flat[(f, "Knee")])
        print(f"{f}: published 2D elbow {np.mean(flat[(f, 'Elbow')]):.2f} knee {np.mean(flat[(f, 'Knee')]):.2f}")
        for name in VARIANTS:
            e = errors[name]
            both = np.mean(e[(f, "Elbow")] + e[(f, "Knee")])
            clear, wrong = signs[name]
            print(f"  {name:18s} elbow {np.mean(e[(f, 'Elbow')]):5.2f} knee {np.mean(e[(f, 'Knee')]):5.2f} "
                  f"both {both:5.2f} ratio {both / both_2d:.3f}   "
                  f"segments on the wrong side {wrong / clear:.1%}")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
