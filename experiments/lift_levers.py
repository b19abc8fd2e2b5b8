"""Lifting levers measured on held-out folds and not adopted: the mirror average, a
symmetrised prior and a confidence threshold, beside any LiftConfig variant.

    python experiments/lift_levers.py --syrip-dir ../shared/data/syrip --folds folds --weights=-ema \\
        --variant mirror '{"mirror": "average"}' --variant sym '{"symmetrised": true}' \\
        --variant conf03 '{"min_confidence": 0.3}' --variant now '{}' --out levers.jsonl

A variant is JSON: LiftConfig overrides of `fast`, plus "mirror": "average" (lift the mirror
image too, mirror it back and average the two poses), "symmetrised": true (the prior's noise
prediction averaged with that of the mirrored pose, mirrored back) and "min_confidence" (joints
below it are missing). Rows as benchmarks/calibrate/lift_validation.py writes them; Test100 is never read.
"""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import torch

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root
from benchmarks.calibrate.lift_validation import summarise
from benchmarks.lib.folds import fold_priors

MIRROR_KEYS = ("mirror", "symmetrised", "min_confidence")


def mirrored(points: np.ndarray | torch.Tensor, flip: list[int]) -> np.ndarray | torch.Tensor:
    """Camera-frame points `(..., J, 3)` (numpy or torch) reflected through x = 0, left and right
    joints swapped; a new array (indexing by the list `flip` copies)."""
    out = points[..., flip, :]
    out[..., 0] = -out[..., 0]
    return out


class SymmetrisedNet(torch.nn.Module):
    """A prior network whose noise prediction is averaged with its mirror's: eps(x) and
    M eps(M x), M the reflection with left and right swapped."""

    def __init__(self, net: torch.nn.Module, flip: list[int]) -> None:
        super().__init__()
        self.net, self.flip = net, flip

    def forward(self, x: torch.Tensor, t: torch.Tensor) -> torch.Tensor:
        eps = self.net(torch.cat([x, mirrored(x, self.flip)]), t)
        return (eps[: len(x)] + mirrored(eps[len(x) :], self.flip)) / 2


def lift_variant(prior, kp, mats: np.ndarray, cfg, lever: dict) -> np.ndarray:
    """Camera-frame poses `(N, J, 3)` of `kp` lifted with `cfg` and the levers of `lever`."""
    from zedo_cli.lifting.solver import lift

    flip = prior.skeleton.flip_permutation
    if lever.get("symmetrised"):
        prior = replace(prior, model=SymmetrisedNet(prior.model, flip))
    xy, conf, floor = kp.xy, kp.confidence, lever.get("min_confidence", 0.0)
    if lever.get("mirror") != "average":
        return lift(xy, conf, mats, prior, cfg, min_confidence=floor).poses_camera
    other = xy[:, flip].copy()
    other[..., 0] = 2.0 * mats[:, None, 0, 2] - other[..., 0]  # the mirror image about the principal point
    both = lift(np.concatenate([xy, other]), np.concatenate([conf, conf[:, flip]]), np.concatenate([mats, mats]),
                prior, cfg, min_confidence=floor).poses_camera  # fmt: skip
    own, back = both[: len(xy)], mirrored(both[len(xy) :], flip)
    return np.where(np.isfinite(back), (own + back) / 2, own)


def main() -> int:
    from zedo_cli.data.skeleton import center_on_root
    from zedo_cli.evaluation.plausibility import symmetry_angle_error_deg, twin_ratio_fractions
    from zedo_cli.evaluation.syrip_benchmark import score_poses
    from zedo_cli.lifting.camera import resolve_intrinsics
    from zedo_cli.lifting.config import get_preset

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--syrip-dir", required=True)
    ap.add_argument("--folds", type=Path, required=True)
    ap.add_argument("--variant", nargs=2, action="append", metavar=("NAME", "JSON"), required=True)
    ap.add_argument("--weights", default="", help="suffix of the fold prior files ('' raw, '-ema' EMA)")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--out", type=Path, required=True)
    args = ap.parse_args()
    torch.set_num_threads(args.threads)
    for k, prior, truth, inputs in fold_priors(args.folds, args.weights, args.syrip_dir):
        for name, text in args.variant:
            spec = json.loads(text)
            lever = {key: spec.pop(key) for key in MIRROR_KEYS if key in spec}
            cfg = replace(get_preset("fast"), **spec)
            for kind, kp in inputs.items():
                kp = kp.to_skeleton(prior.skeleton)
                mats, _ = resolve_intrinsics(kp.image_sizes, kp.image_ids, kp.file_names)
                pred = center_on_root(lift_variant(prior, kp, mats, cfg, lever), prior.skeleton)
                mpjpe, pa, _ = score_poses(pred, truth.poses, prior.skeleton.joints)
                twins = twin_ratio_fractions(pred, prior.skeleton)
                symmetry = symmetry_angle_error_deg(pred, truth.poses, prior.skeleton)
                row = {"fold": k, "variant": name, "input": kind, "weights": args.weights, "config": json.loads(text),
                       "mpjpe_mm": round(mpjpe, 2), "pa_mpjpe_mm": round(pa, 2),
                       "twin_over_1_3": round(twins[1.3], 3), "twin_over_1_6": round(twins[1.6], 3),
                       "symmetry_error_deg": round(symmetry, 2)}  # fmt: skip
                with args.out.open("a") as fh:
                    fh.write(json.dumps(row) + "\n")
                print(json.dumps(row), file=sys.stderr, flush=True)
    summarise([json.loads(line) for line in args.out.read_text().splitlines()])
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
