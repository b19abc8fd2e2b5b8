"""Score lifting settings on held-out SyRIP training poses, never on Test100.

For every fold of `benchmarks/lib/folds.py` whose prior exists (FOLDS/fold<k>.safetensors, trained
on that fold's 450 poses), lift the fold's 150 held-out poses from ground-truth and FiDIP 2D
with each variant (JSON overrides of a preset's LiftConfig) and report, per variant and input:
MPJPE, PA-MPJPE, the fractions of poses whose twin-limb ratio exceeds 1.3 and 1.6, the mean
symmetry-angle error against the weak ground truth, and poses/s.

    python benchmarks/calibrate/lift_validation.py --syrip-dir ../shared/data/syrip --folds folds/ \\
        --variant base '{}' --variant twin '{"twin_rate": 0.3}' --out val-lift.jsonl

Every (fold, variant, input) appends one JSON line to --out (an interrupted sweep resumes);
with --errors DIR the per-joint errors and hypothesis spreads are saved for calibration
(benchmarks/calibrate/calibrate_uncertainty.py).
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the repository root
from benchmarks.lib.folds import fold_priors


def score_variant(prior, truth, kp, cfg, seed: int) -> tuple[dict, dict]:
    """One variant's row (zedo benchmark's measures, `lift_and_score`) and its per-joint errors."""
    from zedo_cli.data.skeleton import center_on_root
    from zedo_cli.evaluation.syrip_benchmark import lift_and_score

    score, res = lift_and_score(prior, truth, kp, cfg, seed=seed)
    pred = center_on_root(res.poses_camera, prior.skeleton)
    row = {"mpjpe_mm": round(score.mpjpe_mm, 2), "pa_mpjpe_mm": round(score.pa_mpjpe_mm, 2),
           "twin_over_1_3": round(score.twin_over_1_3, 3), "twin_over_1_6": round(score.twin_over_1_6, 3),
           "symmetry_error_deg": round(score.symmetry_error_deg, 2), "lifted": int(res.lifted.sum()),
           "poses_per_second": round(score.poses_per_second, 1)}  # fmt: skip
    if res.hypotheses is not None:
        from zedo_cli.lifting.uncertainty import joint_spread

        spread = joint_spread(res.hypotheses, pred)
        err = np.linalg.norm(pred - truth.poses, axis=-1)
        row["spread_mm"] = round(float(np.nanmean(spread)) * 1000, 1)
        row["spread_error_corr"] = round(float(np.corrcoef(spread.ravel(), err.ravel())[0, 1]), 3)
    errors = {"error_m": np.linalg.norm(pred - truth.poses, axis=-1), "hypotheses": res.hypotheses,
              "pose": pred, "truth": truth.poses, "confidence": kp.to_skeleton(prior.skeleton).confidence}  # fmt: skip
    return row, errors


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--syrip-dir", required=True)
    ap.add_argument("--folds", type=Path, required=True)
    ap.add_argument("--variant", nargs=2, action="append", metavar=("NAME", "JSON"), required=True)
    ap.add_argument("--preset", default="fast")
    ap.add_argument("--weights", default="", help="suffix of the fold prior files ('' raw, '-ema' EMA)")
    ap.add_argument("--inputs", nargs="+", default=["gt", "detected"])
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--threads", type=int, default=1, help="torch threads (1: share the CPUs with other runs)")
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--errors", type=Path, default=None, help="save per-joint errors and hypotheses here")
    args = ap.parse_args()

    import torch

    from zedo_cli.lifting.config import get_preset

    torch.set_num_threads(args.threads)
    done = {(r["fold"], r["variant"], r["input"], r.get("weights", "")) for r in _rows(args.out)}
    base = get_preset(args.preset)
    for k, prior, truth, inputs in fold_priors(args.folds, args.weights, args.syrip_dir):
        for name, overrides in args.variant:
            cfg = replace(base, **json.loads(overrides))
            for kind in args.inputs:
                if (k, name, kind, args.weights) in done:
                    continue
                row, errors = score_variant(prior, truth, inputs[kind], cfg, args.seed)
                row = {
                    "fold": k,
                    "variant": name,
                    "input": kind,
                    "weights": args.weights,
                    "config": json.loads(overrides),
                    **row,
                }
                with args.out.open("a") as fh:
                    fh.write(json.dumps(row) + "\n")
                print(json.dumps(row), file=sys.stderr, flush=True)
                if args.errors is not None:
                    args.errors.mkdir(parents=True, exist_ok=True)
                    arrays = {key: v for key, v in errors.items() if v is not None}
                    np.savez(args.errors / f"fold{k}{args.weights}-{name}-{kind}.npz", **arrays)
    summarise(_rows(args.out))
    return 0


def _rows(path: Path) -> list[dict]:
    return [json.loads(line) for line in path.read_text().splitlines()] if path.exists() else []


def summarise(rows: list[dict]) -> None:
    fields = (
        "mpjpe_mm",
        "pa_mpjpe_mm",
        "twin_over_1_3",
        "twin_over_1_6",
        "symmetry_error_deg",
        "poses_per_second",
        "spread_mm",
        "spread_error_corr",
    )
    print("| variant | weights | input | folds | " + " | ".join(fields) + " |")
    print("|" + " --- |" * (4 + len(fields)))
    keys = sorted({(r["variant"], r.get("weights", ""), r["input"]) for r in rows})
    for variant, weights, kind in keys:
        mine = [r for r in rows if (r["variant"], r.get("weights", ""), r["input"]) == (variant, weights, kind)]
        cells = [f"{statistics.mean(r[f] for r in mine):.3g}" if all(f in r for r in mine) else "-" for f in fields]
        print(f"| {variant} | {weights or 'raw'} | {kind} | {len(mine)} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    raise SystemExit(main())
