"""A tried and rejected remedy for the knee's clip mean angle (docs/movement.md, "What limits the knee's mean
angle"): replace each frame's elbow or knee angle by its expectation over the four depth signs of the limb's
two segments, with probabilities learned on held-out synthetic clips.

A segment that keeps its 2D and its length can point to either side of the camera's depth axis; flipping the
upper and the lower segment (orthographically: negating the z of the joint-to-joint vector) gives four
candidate angles per frame. Per fold prior `fold<k>.safetensors` in `--folds`: features_3d_accuracy.py's case
clips (56 clips of 14 s, `--interpolation` motion) are lifted (default preset, `--temporal smooth`) and smoothed
as `features_3d` smooths; per part (elbow, knee; both sides pooled) the share of frames whose true depth signs
are each of the four, given the lifted signs and |unit z| of the two segments in 3 bins (a 36 x 4 table,
smoothed towards "as lifted"). Fitted on one fold's clips, applied to the other's, it prints:

- synthetic clips: the mean absolute error of the clip mean angle against the truth's, lifted as it is and as
  the expectation; and the mean signed error;
- real images: the fold's 150 held-out SyRIP training images (ground-truth and FiDIP 2D) lifted by the fold's
  prior, the per-image angle's mean absolute and signed error against the weak 3D truth, both ways.

Test100 and SyRIP's synthetic rows are never read.

    OMP_NUM_THREADS=2 .venv/bin/python experiments/depth_sign_expectation.py --syrip-dir ../shared/data/syrip \
        --folds FOLDS
"""

from __future__ import annotations

import itertools
import sys
from pathlib import Path

import numpy as np
import torch

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root
from benchmarks.calibrate.features_3d_accuracy import CASE_CLIPS
from benchmarks.lib.folds import fold_clip_args, fold_priors
from benchmarks.lib.settings import CLIP_SETTINGS
from zedo_cli.analysis.clip.published_features import Windows, smooth_positions
from zedo_cli.analysis.pose.geometry import angle_between_deg
from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.evaluation.clips.eased import make_sequences

SKELETON = get_skeleton("syrip12")
LIMBS = {"Elbow": ("shoulder", "elbow", "wrist"), "Knee": ("hip", "knee", "ankle")}
EDGES = (0.15, 0.4)  # |unit z| bins of each segment
CELLS = 4 * (len(EDGES) + 1) ** 2
SMOOTHING = 4.0  # pseudo-counts of "as lifted" per cell


def candidates(poses: np.ndarray, side: str, part: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per frame of `poses (T, J, 3)`: the four angles `(T, 4)` (upper, lower segment kept or flipped in depth;
    column 0 as lifted) and the unit z `(T,)` of the upper and the lower segment."""
    a, m, b = (poses[:, SKELETON.index(f"{side}_{j}")] for j in LIMBS[part])
    upper, lower = m - a, b - m
    angles = [
        angle_between_deg(-upper * [1, 1, fu], lower * [1, 1, fl]) for fu, fl in itertools.product((1, -1), (1, -1))
    ]
    return (
        np.stack(angles, 1),
        upper[:, 2] / np.linalg.norm(upper, axis=-1),
        lower[:, 2] / np.linalg.norm(lower, axis=-1),
    )


def cell(z_upper: np.ndarray, z_lower: np.ndarray) -> np.ndarray:
    n = len(EDGES) + 1
    signs = (z_upper > 0) * 2 + (z_lower > 0)
    return signs * n * n + np.digitize(np.abs(z_upper), EDGES) * n + np.digitize(np.abs(z_lower), EDGES)


def fit_table(pairs: list[tuple[np.ndarray, np.ndarray]], part: str) -> np.ndarray:
    """`(CELLS, 4)` probabilities of the true depth signs relative to the lifted ones, from (lifted, truth) clips."""
    counts = np.zeros((CELLS, 4))
    counts[:, 0] = SMOOTHING
    for lifted, truth in pairs:
        for side in ("left", "right"):
            angles, zu, zl = candidates(lifted, side, part)
            _, tu, tl = candidates(truth, side, part)
            ok = np.isfinite(angles).all(1) & np.isfinite(tu) & np.isfinite(tl)
            label = (np.sign(tu) != np.sign(zu)) * 2 + (np.sign(tl) != np.sign(zl))
            np.add.at(counts, (cell(zu, zl)[ok], label[ok]), 1)
    return counts / counts.sum(1, keepdims=True)


def expected(poses: np.ndarray, side: str, part: str, table: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """As-lifted and expected angle `(T,)` each (NaN where a joint is unknown)."""
    angles, zu, zl = candidates(poses, side, part)
    ok = np.isfinite(angles).all(1)
    out = np.full(len(poses), np.nan)
    out[ok] = (table[cell(zu[ok], zl[ok])] * angles[ok]).sum(1)
    return angles[:, 0], out


def main() -> int:
    from zedo_cli.evaluation.syrip_benchmark import lift_and_score
    from zedo_cli.lifting.config import DEFAULT_PRESET, get_preset
    from zedo_cli.lifting.temporal import lift_sequence

    args = fold_clip_args(__doc__, interpolation="positions")
    cfg = get_preset(DEFAULT_PRESET)
    windows = Windows(CLIP_SETTINGS["fps"])
    clips, images = {}, {}
    for k, prior, truth, inputs in fold_priors(args.folds, "", args.syrip_dir):
        torch.manual_seed(k)
        seq = make_sequences(truth.poses, np.random.default_rng(300 + k), **{**CLIP_SETTINGS, **CASE_CLIPS},
                             interpolation=args.interpolation)  # fmt: skip
        res = lift_sequence(seq["xy"], seq["conf"], seq["k"], prior, cfg, mode="smooth", tracks=seq["tracks"])
        lifted = np.where(res.lifted[:, None, None], res.poses_root_relative, np.nan)  # (N, J, 3)
        clips[k] = [(smooth_positions(lifted[seq["tracks"] == t], windows), seq["rel"][seq["tracks"] == t])
                    for t in np.unique(seq["tracks"])]  # fmt: skip
        for source in ("gt", "detected"):
            _, lift = lift_and_score(prior, truth, inputs[source], cfg, input_2d=source)
            images[k, source] = (np.where(lift.lifted[:, None, None], lift.poses_camera, np.nan), truth.poses)
    if len(clips) < 2:
        print(f"need two fold priors fold<k>.safetensors in {args.folds}", file=sys.stderr)
        return 1
    print(
        "| part | fold | synthetic clips: clip mean MAE, lifted -> expected | signed | "
        "real images GT 2D: MAE | signed | FiDIP 2D: MAE | signed |"
    )
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for part, k in itertools.product(LIMBS, clips):
        table = fit_table([p for j, c in clips.items() if j != k for p in c], part)
        err = []  # (clip-side, lifted | expected) signed errors of the clip mean angle
        for lifted, truth in clips[k]:
            for side in ("left", "right"):
                raw, exp = expected(lifted, side, part, table)
                t = candidates(truth, side, part)[0][:, 0]
                ok = np.isfinite(raw) & np.isfinite(t)
                err.append((raw[ok].mean() - t[ok].mean(), exp[ok].mean() - t[ok].mean()))
        e = np.array(err)
        cells = [
            f"{np.abs(e[:, 0]).mean():.2f} -> {np.abs(e[:, 1]).mean():.2f}",
            f"{e[:, 0].mean():+.1f} -> {e[:, 1].mean():+.1f}",
        ]
        for source in ("gt", "detected"):
            lifted, truth = images[k, source]
            d = []
            for side in ("left", "right"):
                raw, exp = expected(lifted, side, part, table)
                t = candidates(truth, side, part)[0][:, 0]
                ok = np.isfinite(raw) & np.isfinite(t)
                d.append(np.stack([raw[ok] - t[ok], exp[ok] - t[ok]], 1))
            d = np.concatenate(d)
            cells += [
                f"{np.abs(d[:, 0]).mean():.2f} -> {np.abs(d[:, 1]).mean():.2f}",
                f"{d[:, 0].mean():+.1f} -> {d[:, 1].mean():+.1f}",
            ]
        print(f"| {part} | {k} | " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
