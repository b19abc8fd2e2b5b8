"""Calibrate `uncertainty_m` on held-out SyRIP training poses and measure its coverage.

Reads the per-joint errors and hypotheses that `benchmarks/calibrate/lift_validation.py --errors DIR`
saved for one variant (fold priors lifting their held-out poses from ground-truth and FiDIP
2D), then

1. measures coverage honestly by cross-fitting: the model is fitted on the other folds (with a
   single fold: on the other half of its poses) and the fraction of true joints within their
   radius is counted on the fold left out, per joint and per input kind;
2. fits the final model on every held-out pose and adds it, for the shipped prior and the
   variant's settings, to the calibration file (default: the package's weights/uncertainty.json).

    python benchmarks/calibrate/calibrate_uncertainty.py --errors val-errors --variant default \\
        --config '{"twin_rate": 0.5, "hypotheses": 8}' --write

Test100 and SyRIP's synthetic rows are never read.
"""

from __future__ import annotations

import argparse
import json
import re
from dataclasses import replace
from pathlib import Path

import numpy as np


def load_errors(folder: Path, variant: str, weights: str = "") -> dict[tuple[int, str], dict[str, np.ndarray]]:
    """Saved errors of `variant` lifted with the fold priors `fold<k><weights>.safetensors`."""
    out = {}
    for path in sorted(folder.glob(f"fold*{weights}-{variant}-*.npz")):
        m = re.fullmatch(rf"fold(\d+){re.escape(weights)}-{re.escape(variant)}-(\w+)\.npz", path.name)
        if m:
            with np.load(path) as data:
                out[int(m.group(1)), m.group(2)] = {k: data[k] for k in data.files}
    return out


def spread_of(d: dict[str, np.ndarray]) -> np.ndarray:
    from zedo_cli.lifting.uncertainty import joint_spread

    return joint_spread(d.get("hypotheses"), d["pose"])


def groups(runs: dict, seed: int = 0) -> list[tuple[np.ndarray, np.ndarray, dict]]:
    """(calibration mask, evaluation mask, ...) splits of the pooled poses: leave one fold out,
    or two random halves when there is one fold."""
    folds = sorted({k for k, _ in runs})
    keys = list(runs)
    fold_of = np.concatenate([np.full(len(runs[key]["error_m"]), key[0]) for key in keys])
    if len(folds) > 1:
        return [(fold_of != f, fold_of == f) for f in folds]
    half = np.random.default_rng(seed).random(len(fold_of)) < 0.5  # one draw per pose and input
    return [(half, ~half), (~half, half)]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--errors", type=Path, required=True)
    ap.add_argument("--variant", required=True)
    ap.add_argument("--weights", default="", help="suffix of the fold priors, as in lift_validation ('-ema')")
    ap.add_argument("--config", default="{}", help="the variant's LiftConfig overrides (JSON), as in lift_validation")
    ap.add_argument("--preset", default="fast")
    ap.add_argument("--prior", default="syrip12-scratch", help="the prior the calibration is for")
    ap.add_argument("--calibration-file", type=Path, default=None)
    ap.add_argument("--write", action="store_true", help="add the fitted model to the calibration file")
    args = ap.parse_args()

    from zedo_cli.data.skeleton import get_skeleton
    from zedo_cli.lifting.config import get_preset
    from zedo_cli.lifting.uncertainty import (
        COVERAGE,
        bundled_calibrations_path,
        calibration_settings,
        fit_model,
        radius_m,  # fmt: skip
        read_calibrations,
        write_calibrations,
    )
    from zedo_cli.prior.weights import file_sha256, resolve_prior_path

    cfg = replace(get_preset(args.preset), **json.loads(args.config))
    runs = load_errors(args.errors, args.variant, args.weights)
    if not runs:
        raise SystemExit(f"no saved errors for variant {args.variant!r} in {args.errors}")
    keys = list(runs)
    error = np.concatenate([runs[k]["error_m"] for k in keys])
    spread = np.concatenate([spread_of(runs[k]) for k in keys])
    kind = np.concatenate([np.full(len(runs[k]["error_m"]), k[1]) for k in keys])
    joints = get_skeleton("syrip12").joints
    sha = file_sha256(resolve_prior_path(args.prior))
    inside = np.zeros_like(error, dtype=bool)
    for calib, evaluate in groups(runs):
        model = fit_model(error[calib], spread[calib], coverage=COVERAGE, prior_sha256=sha, cfg=cfg,
                          joints=joints, provenance={})  # fmt: skip
        inside[evaluate] = error[evaluate] <= radius_m(model, spread[evaluate])
    final = fit_model(error, spread, coverage=COVERAGE, prior_sha256=sha, cfg=cfg, joints=joints, provenance={})
    radius = radius_m(final, spread)
    report = {"coverage_target": COVERAGE, "poses": int(len(error)), "folds": sorted({k for k, _ in keys}),
              "cross_fitted_coverage": {}, "mean_radius_mm": round(float(radius.mean() * 1000), 1),
              "correlation_spread_error": round(float(np.corrcoef(spread.ravel(), error.ravel())[0, 1]), 3)
              if spread.std() > 0 else None}  # fmt: skip
    for name in sorted(set(kind)):
        sel = kind == name
        report["cross_fitted_coverage"][name] = {"all": round(float(inside[sel].mean()), 3),
            "per_joint": {j: round(float(inside[sel, i].mean()), 3) for i, j in enumerate(joints)}}  # fmt: skip
    print(json.dumps(report, indent=1))
    if args.write:
        path = args.calibration_file or bundled_calibrations_path()
        models = read_calibrations(path) if path.exists() else []
        # The provenance names scripts by their paths in the flat benchmarks/ that wrote the shipped file: kept, so
        # that a rerun writes the same file (benchmarks/README.md maps them to today's paths).
        final = replace(final, provenance={
            "data": "SyRIP training poses held out of 4-fold priors (benchmarks/folds.py), GT and FiDIP 2D; "
                    "never Test100 or the synthetic rows", "recipe": "benchmarks/calibrate_uncertainty.py "
                    f"--variant {args.variant} --weights={args.weights} --config '{args.config}'",
            **report})  # fmt: skip
        models = [m for m in models if not (m.prior_sha256 == sha and m.settings == calibration_settings(cfg))]
        write_calibrations(path, [*models, final])
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
