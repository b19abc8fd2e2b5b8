"""How `zedo augment --strength` trades infant-like proportions against keeping the adult posture.

For each strength, convert the same seeded draw of adult poses and report
- proportion gap: the mean over bones of the 1-Wasserstein distance between the distributions of
  bone-length fractions (bone length / skeleton size) of the converted poses and of the infant
  training poses, in percent of the skeleton size (strength 0 gives the adult-infant gap);
- posture change: PA-MPJPE between each adult pose and its conversion, both at the adult's size,
  in mm (how much more than size and proportions moved).
Only infant *training* poses are used, never test poses.

    python benchmarks/accuracy/augment_strength.py --model augmenter.safetensors --adult-dir ../shared/data/adult \\
        --syrip-dir ../shared/data/syrip
"""

from __future__ import annotations

import argparse

import numpy as np


def wasserstein_1d(a: np.ndarray, b: np.ndarray, levels: int = 200) -> float:
    q = (np.arange(levels) + 0.5) / levels
    return float(np.abs(np.quantile(a, q) - np.quantile(b, q)).mean())


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--model", required=True)
    ap.add_argument("--adult-dir", required=True)
    ap.add_argument("--syrip-dir", required=True)
    ap.add_argument("--count", type=int, default=600)
    ap.add_argument("--strengths", nargs="+", type=float, default=[0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.7, 1.0])
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    from zedo_cli.augment.augmenter import load_augmenter
    from zedo_cli.augment.conversion import choose_sources, convert_poses
    from zedo_cli.augment.plots import bone_fractions
    from zedo_cli.data.adult import load_adult_poses
    from zedo_cli.data.datasets import load_syrip_3d
    from zedo_cli.evaluation.metrics import pa_mpjpe_mm

    aug = load_augmenter(args.model)
    skel = aug.skeleton
    infant = bone_fractions(load_syrip_3d(args.syrip_dir, "train").poses, skel)
    adult = load_adult_poses(args.adult_dir, skel.name)
    sources = adult.poses[choose_sources(len(adult.poses), args.count, args.seed)]
    print("| strength | proportion gap (% of size) | posture change PA-MPJPE (mm, adult size) |")
    print("| --- | --- | --- |")
    for strength in args.strengths:
        out = convert_poses(aug.model, aug.sde, aug.sizes, skel, sources, strength=strength, scale="keep",
                            seed=args.seed)  # fmt: skip
        fractions = bone_fractions(out, skel)
        gap = np.mean([wasserstein_1d(fractions[:, b], infant[:, b]) for b in range(len(skel.bones))])
        print(f"| {strength:g} | {100 * gap:.2f} | {pa_mpjpe_mm(out, sources):.1f} |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
