"""How close the `3d_` clip features of lifted clips and the published 2D features come to the 3D truth
(issue 35, part 2): elbow and knee `mean_angle` and `median_vel_angle`.

For every fold prior `fold<k><weights>.safetensors` in `--folds` (benchmarks/folds.py), the fold's 150
held-out SyRIP training poses make synthetic clips (benchmarks/temporal.py's generator with
calibrate_measures.CLIP_SETTINGS: 16 clips of 5 s at 30 fps, eased between 6 key poses, turning and
drifting, 1 m from the pseudo camera, 3 px noise, 3 % of joints dropped, a 3-frame gap), whose 2D is
lifted with the default preset in `--temporal smooth` as calibrate_measures.py lifts them. Per clip:

- truth: `features_3d` of the clip's true 3D joints (the same smoothing and statistics);
- 3D: `features_3d` of the lifted poses (`3d_mean_angle_<L|R><Elbow|Knee>`, `3d_median_vel_angle_...`);
- 2D: `published_features` of the clip's 2D (`mean_angle_...`, `median_vel_angle_...`, the interior angle
  in the image, the same convention as the 3D one).

It prints the mean absolute error against the truth over (clip, side) of each, per fold and pooled, and the
ratio 3D / 2D (target: at most 0.5). Test100 and SyRIP's synthetic rows are never read.

    /work/main/.venv/bin/python benchmarks/features_3d_accuracy.py --syrip-dir ../shared/data/syrip --folds /work/folds
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from zedo_cli.analysis.features_3d import features_3d
from zedo_cli.analysis.published_features import published_features
from zedo_cli.data.skeleton import get_skeleton

SKELETON = get_skeleton("syrip12")
FEATURES = ("mean_angle", "median_vel_angle")
JOINTS = ("LElbow", "RElbow", "LKnee", "RKnee")


def clip_errors(xy: np.ndarray, lifted: np.ndarray, truth: np.ndarray, fps: float, size: np.ndarray) -> dict:
    """Per feature and joint of one clip: |3D - truth| and |2D - truth| (degrees, deg/s)."""
    true = features_3d(truth, SKELETON, fps).values
    ours = features_3d(lifted, SKELETON, fps).values
    flat = published_features(xy, SKELETON, fps, size).values
    out = {}
    for f in FEATURES:
        for j in JOINTS:
            t = true[f"3d_{f}_{j}"]
            out[(f, j)] = (abs(ours[f"3d_{f}_{j}"] - t), abs(flat[f"{f}_{j}"] - t))
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--syrip-dir", required=True)
    ap.add_argument("--folds", type=Path, required=True)
    ap.add_argument("--weights", default="", help="suffix of the fold priors' files (fold<k><weights>.safetensors)")
    args = ap.parse_args()

    import torch
    from calibrate_measures import CLIP_SETTINGS
    from folds import fold_priors
    from temporal import IMAGE_H, IMAGE_W, make_sequences

    from zedo_cli.lifting.config import DEFAULT_PRESET, get_preset
    from zedo_cli.lifting.temporal import lift_sequence

    cfg = get_preset(DEFAULT_PRESET)
    size = np.array([IMAGE_W, IMAGE_H], dtype=float)
    fps = float(CLIP_SETTINGS["fps"])
    errors: dict[int, list[dict]] = {}
    for k, prior, truth, _ in fold_priors(args.folds, args.weights, args.syrip_dir):
        torch.manual_seed(k)
        clips = make_sequences(truth.poses, np.random.default_rng(100 + k), **CLIP_SETTINGS)
        res = lift_sequence(clips["xy"], clips["conf"], clips["k"], prior, cfg, mode="smooth", tracks=clips["tracks"])
        lifted = np.where(res.lifted[:, None, None], res.poses_root_relative, np.nan)  # (N, J, 3)
        errors[k] = []
        for track in np.unique(clips["tracks"]):
            at = clips["tracks"] == track
            errors[k].append(clip_errors(clips["xy"][at], lifted[at], clips["rel"][at], fps, size))
        print(f"fold {k}: {int(at.sum())} frames a clip, {len(errors[k])} clips, "
              f"{int(res.lifted.sum())}/{len(res.lifted)} frames lifted", flush=True)  # fmt: skip
    if not errors:
        print(f"no fold prior fold<k>{args.weights}.safetensors in {args.folds}", file=sys.stderr)
        return 1

    def table(name: str, runs: list[dict]) -> None:
        print(f"\n### {name}: MAE against the 3D truth over {len(runs)} clips x 2 sides")
        print("| feature | joint | 3D (3d_) | 2D (published) | 3D / 2D |")
        print("| --- | --- | --- | --- | --- |")
        for f in FEATURES:
            unit = "deg" if f == "mean_angle" else "deg/s"
            both = []
            for part in ("Elbow", "Knee"):
                e = np.array([r[(f, s + part)] for r in runs for s in "LR"])  # (clips x 2, 2)
                both.append(e)
                m3, m2 = np.nanmean(e, axis=0)
                print(f"| {f} ({unit}) | {part} | {m3:.1f} | {m2:.1f} | {m3 / m2:.2f} |")
            m3, m2 = np.nanmean(np.concatenate(both), axis=0)
            print(f"| {f} ({unit}) | both | **{m3:.1f}** | **{m2:.1f}** | **{m3 / m2:.2f}** |")

    for k, runs in errors.items():
        table(f"fold {k}", runs)
    if len(errors) > 1:
        table(f"folds {', '.join(map(str, errors))} pooled", [r for runs in errors.values() for r in runs])
    return 0


if __name__ == "__main__":
    sys.exit(main())
