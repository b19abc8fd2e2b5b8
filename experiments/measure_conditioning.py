"""Would conditioning the symmetry intervals on how far the limbs point at the camera make more
single-image calls decisive? (An experiment on held-out lifts only.)

A segment that points towards or away from the camera gets its depth from the prior, so its
symmetry angle is guessed; one lying in the image plane is seen. Per pair the case feature is
the larger |camera-z component| of the two lifted segments' unit directions. Each fold prior
lifts its fold's held-out training poses (GT and FiDIP 2D, default preset, pseudo camera); then,
leaving one fold out, the shipped estimator (shrinkage) is fitted with Mondrian split-conformal
bins of: the measured value (what zedo ships), the feature, or both (2 x 2), and the held-out
share of decisive calls, their agreement with the truth's call and the 90 % coverage are printed.

    python experiments/measure_conditioning.py --syrip-dir ../shared/data/syrip --folds folds/

Test100 and SyRIP's synthetic rows are never read.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root
from benchmarks.calibrate.calibrate_measures import SKELETON, case_arrays
from zedo_cli.analysis.pose.symmetry import DEFAULT_THRESHOLD_DEG, PAIRS, measure_name
from zedo_cli.analysis.uncertainty.calibration import conformal_quantile, fit_measure, residuals


def towards_camera(poses: np.ndarray, pair: str) -> np.ndarray:
    """(N,) the larger |z| of the left and right segments' unit directions (camera frame)."""
    a, b, _ = PAIRS[pair]
    out = []
    for side in ("left", "right"):
        j0, j1 = SKELETON.joints.index(f"{side}_{a}"), SKELETON.joints.index(f"{side}_{b}")
        d = poses[:, j1] - poses[:, j0]
        out.append(np.abs(d[:, 2]) / np.maximum(np.linalg.norm(d, axis=1), 1e-9))
    return np.maximum(*out)


def lift_cases(args: argparse.Namespace) -> dict[str, np.ndarray]:
    from benchmarks.lib.folds import fold_priors
    from zedo_cli.lifting.camera import resolve_intrinsics
    from zedo_cli.lifting.config import DEFAULT_PRESET, get_preset
    from zedo_cli.lifting.solver import lift

    cfg = get_preset(DEFAULT_PRESET)
    cases: dict[str, list[np.ndarray]] = {}
    for k, prior, truth, inputs in fold_priors(args.folds, "", args.syrip_dir):
        for key, kp in inputs.items():
            kp = kp.to_skeleton(prior.skeleton)
            mats, _ = resolve_intrinsics(kp.image_sizes, kp.image_ids, kp.file_names)
            res = lift(kp.xy, kp.confidence, mats, prior, cfg, seed=0)
            # the shipped calibration's cases: NaN where a joint the measure uses was not observed
            arrays = case_arrays(res.poses_root_relative, res.observed, res.lifted, truth.poses)
            for pair in PAIRS:
                n = measure_name(pair)
                cases.setdefault(f"{n}|raw", []).append(arrays[f"{n}|raw"])
                cases.setdefault(f"{n}|truth", []).append(arrays[f"{n}|truth"])
                cases.setdefault(f"{n}|feature", []).append(towards_camera(res.poses_root_relative, pair))
            cases.setdefault("fold", []).append(np.full(len(kp), k))
            cases.setdefault("input", []).append(np.full(len(kp), key))
            print(f"fold {k} {key}: {int(res.lifted.sum())}/{len(kp)} lifted")
    return {k: np.concatenate(v) for k, v in cases.items()}


def mondrian(r: np.ndarray, bins: np.ndarray, nbins: int, level: float) -> tuple[np.ndarray, np.ndarray]:
    lo = np.array([conformal_quantile(-r[bins == b], (1 + level) / 2) for b in range(nbins)])
    hi = np.array([conformal_quantile(r[bins == b], (1 + level) / 2) for b in range(nbins)])
    return lo, hi


def evaluate(cases: dict[str, np.ndarray], scheme: str, level: float, threshold: float) -> dict[str, float]:
    decisive = agree = covered = total = 0
    for f in np.unique(cases["fold"]):
        fit_mask, test_mask = cases["fold"] != f, cases["fold"] == f
        for pair in PAIRS:
            n = measure_name(pair)
            raw, truth, feat = cases[f"{n}|raw"], cases[f"{n}|truth"], cases[f"{n}|feature"]
            ok = np.isfinite(raw) & np.isfinite(truth)
            fm, tm = fit_mask & ok, test_mask & ok
            model = fit_measure(raw[fm], truth[fm], circular=False, bins=1)
            est = model.estimate(raw)
            r = residuals(truth, est, False)
            v_edge = np.quantile(raw[fm], [0.5])
            f_edge = np.quantile(feat[fm], [0.5])
            v_bin, f_bin = np.searchsorted(v_edge, raw), np.searchsorted(f_edge, feat)
            bins, nb = {"value": (v_bin, 2), "feature": (f_bin, 2), "both": (2 * v_bin + f_bin, 4)}[scheme]
            lo_q, hi_q = mondrian(r[fm], bins[fm], nb, level)
            lo_q90, hi_q90 = mondrian(r[fm], bins[fm], nb, 0.9)
            lo, hi = est - lo_q[bins], est + hi_q[bins]
            call = np.where(hi <= threshold, 1, np.where(lo > threshold, 2, 0))[tm]
            ref = np.where(truth <= threshold, 1, 2)[tm]
            decisive += int((call > 0).sum())
            agree += int(((call > 0) & (call == ref)).sum())
            covered += int(((truth >= est - lo_q90[bins]) & (truth <= est + hi_q90[bins]))[tm].sum())
            total += int(tm.sum())
    return {"decisive": decisive / total, "agreement": agree / max(decisive, 1), "coverage90": covered / total}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--syrip-dir", required=True)
    ap.add_argument("--folds", type=Path, required=True)
    ap.add_argument("--threshold", type=float, default=DEFAULT_THRESHOLD_DEG)
    args = ap.parse_args()
    cases = lift_cases(args)
    print("| input | bins | level | decisive | agreement | 90 % coverage |\n| --- | --- | --- | --- | --- | --- |")
    for key in ("gt", "detected"):
        sub = {k: v[cases["input"] == key] for k, v in cases.items()}
        for scheme in ("value", "feature", "both"):
            for level in (0.7, 0.8, 0.9):
                s = evaluate(sub, scheme, level, args.threshold)
                print(
                    f"| {key} | {scheme} | {level} | {100 * s['decisive']:.1f} % | {100 * s['agreement']:.1f} % | "
                    f"{100 * s['coverage90']:.1f} % |"
                )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
