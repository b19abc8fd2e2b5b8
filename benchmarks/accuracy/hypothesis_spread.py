"""Does the spread of a lift's hypotheses tell which poses went wrong (unstable solutions)?

For every fold prior in FOLDS (fold<k>.safetensors), lift the fold's held-out SyRIP training poses
(never Test100) from ground-truth and FiDIP 2D with `fast` and 8 hypotheses, and relate each pose's
`hypothesis_spread_m` (the hypotheses' RMS distance from the reported pose at their most different
joint) to its error (MPJPE against the 3D truth, root-relative). Prints, per threshold, the share
of poses flagged, the mean error of the flagged and of the others, and how many of the poses with
an error over 80 mm the flag catches.

    .venv/bin/python benchmarks/accuracy/hypothesis_spread.py --syrip-dir ../shared/data/syrip --folds folds
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the repository root
from benchmarks.lib.folds import fold_priors

THRESHOLDS_MM = (20, 30, 40, 50, 60, 80, 100)
BAD_MM = 80.0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--syrip-dir", type=Path, required=True)
    parser.add_argument("--folds", type=Path, required=True)
    parser.add_argument("--hypotheses", type=int, default=8)
    args = parser.parse_args()

    from zedo_cli.data.skeleton import center_on_root
    from zedo_cli.lifting.camera import resolve_intrinsics
    from zedo_cli.lifting.config import get_preset
    from zedo_cli.lifting.solver import lift

    cfg = replace(get_preset("fast"), hypotheses=args.hypotheses)
    spreads, errors = [], []
    for k, prior, truth, inputs in fold_priors(args.folds, "", args.syrip_dir):
        for name, kp in inputs.items():
            kp = kp.to_skeleton(prior.skeleton)
            mats, _ = resolve_intrinsics(kp.image_sizes, kp.image_ids, kp.file_names)
            res = lift(kp.xy, kp.confidence, mats, prior, cfg)
            pred = center_on_root(res.poses_camera, prior.skeleton)
            err = np.linalg.norm(pred - truth.poses, axis=-1).mean(1) * 1000  # (N,) mm
            assert res.hypothesis_spread_m is not None
            spread = res.hypothesis_spread_m * 1000
            ok = res.lifted & np.isfinite(spread)
            print(f"fold {k} {name}: {int(ok.sum())} poses, spread median {np.median(spread[ok]):.1f} mm, "
                  f"correlation with the error {np.corrcoef(spread[ok], err[ok])[0, 1]:.2f}")  # fmt: skip
            spreads.append(spread[ok])
            errors.append(err[ok])
    spread, err = np.concatenate(spreads), np.concatenate(errors)
    bad = err > BAD_MM
    print(f"\nall: {len(err)} poses, correlation {np.corrcoef(spread, err)[0, 1]:.2f}, "
          f"{int(bad.sum())} with an error over {BAD_MM:g} mm; spread percentiles 50/90/99: "
          " / ".join(f"{np.percentile(spread, q):.1f}" for q in (50, 90, 99)) + " mm\n")  # fmt: skip
    print(f"| threshold (mm) | poses flagged | mean error flagged (mm) | mean error others (mm) | "
          f"errors over {BAD_MM:g} mm caught |")  # fmt: skip
    print("| --- | --- | --- | --- | --- |")
    for t in THRESHOLDS_MM:
        flag = spread > t
        flagged = f"{err[flag].mean():.1f}" if flag.any() else "-"
        others = f"{err[~flag].mean():.1f}" if (~flag).any() else "-"
        caught = f"{int((flag & bad).sum())} of {int(bad.sum())}"
        print(f"| {t} | {flag.mean():.1%} | {flagged} | {others} | {caught} |")


if __name__ == "__main__":
    main()
