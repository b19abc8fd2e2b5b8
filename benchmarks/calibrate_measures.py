"""Calibrate the measure-level estimates and intervals of `zedo analyze` on held-out lifts (issue 28).

1. `--lift`: every fold prior `fold<k><weights>.safetensors` in `--folds` (benchmarks/folds.py)
   lifts its fold's held-out SyRIP training poses with the default preset and the pseudo camera,
   from ground-truth and FiDIP 2D (images), and synthetic clips made from the same held-out poses
   (benchmarks/temporal.py's generator, 30 fps, 3 px noise) in `--temporal smooth` (videos). For
   every case it saves the raw measures of the lift, their depth sensitivities and the measures
   of the truth (`--cases DIR`, one npz per fold, input and mode).
2. Then, per mode, it cross-fits (leave one fold out; with one fold, two halves of its poses or
   clips) and prints, on the cases each model never saw: the mean absolute error of the raw and
   the calibrated estimates, the coverage of the intervals per measure, and for the symmetry pairs
   the share of decisive calls and their agreement with the truth's call at every level.
3. `--write`: fits on every case and writes the calibrations (default: the package's
   weights/measures.json) for the shipped prior.

    python benchmarks/folds.py --syrip-dir ../shared/data/syrip --out folds/
    zedo fit-prior folds/fold0-train.npz --recipe weights_spec/syrip12-scratch.toml --out folds/fold0.safetensors
    python benchmarks/calibrate_measures.py --syrip-dir ../shared/data/syrip --folds folds/ --cases cases/ \\
        --lift --write

Test100 and SyRIP's synthetic rows are never read.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from zedo_cli.analysis.analyse import SYMMETRY_NAMES, all_measures
from zedo_cli.analysis.calibration import (
    LEVELS,
    MeasureCalibration,
    MeasureModel,
    bundled_path,
    fit_measure,
    measure_joints,
    read_calibrations,
    residuals,
    write_calibrations,
)
from zedo_cli.analysis.joint_angles import CIRCULAR_ANGLES
from zedo_cli.analysis.symmetry import DEFAULT_THRESHOLD_DEG
from zedo_cli.data.skeleton import get_skeleton

SKELETON = get_skeleton("syrip12")
BINS = {"none": 2, "smooth": 4}  # bins of the measured value per measure (images: ~300 cases a fold, clips: ~2400)
CLIP_SETTINGS = {"count": 16, "keyposes": 6, "transition_s": 1.0, "fps": 30.0, "noise_px": 3.0, "drop": 0.03, "gap": 3}


def measures(p: np.ndarray) -> dict[str, np.ndarray]:
    return all_measures(p, SKELETON)


def case_arrays(lifted: np.ndarray, observed: np.ndarray, ok: np.ndarray, truth: np.ndarray) -> dict[str, np.ndarray]:
    """Per measure: raw value and truth of every case; the raw value NaN where a joint it uses was
    filled by the prior or the pose was not lifted (such cases are never calibrated)."""
    raw, true = measures(lifted), measures(truth)
    uses = measure_joints(SKELETON, measures, list(raw))
    out = {}
    for name in raw:
        usable = ok & observed[:, uses[name]].all(1)
        out[f"{name}|raw"] = np.where(usable, raw[name], np.nan)
        out[f"{name}|truth"] = true[name]
    return out


def lift_cases(args: argparse.Namespace) -> None:
    import torch
    from folds import fold_priors
    from temporal import make_sequences

    from zedo_cli.lifting.camera import resolve_intrinsics
    from zedo_cli.lifting.config import DEFAULT_PRESET, get_preset
    from zedo_cli.lifting.solver import lift
    from zedo_cli.lifting.temporal import lift_sequence

    cfg = get_preset(DEFAULT_PRESET)
    args.cases.mkdir(parents=True, exist_ok=True)
    for k, prior, truth, inputs in fold_priors(args.folds, args.weights, args.syrip_dir):
        for key, kp in inputs.items():
            kp = kp.to_skeleton(prior.skeleton)
            mats, _ = resolve_intrinsics(kp.image_sizes, kp.image_ids, kp.file_names)
            res = lift(kp.xy, kp.confidence, mats, prior, cfg, seed=0)
            arrays = case_arrays(res.poses_root_relative, res.observed, res.lifted, truth.poses)
            np.savez(args.cases / f"fold{k}-none-{key}.npz", group=np.arange(len(kp)), **arrays)
            print(f"fold {k} {key}: {int(res.lifted.sum())}/{len(kp)} lifted")
        torch.manual_seed(k)
        clips = make_sequences(truth.poses, np.random.default_rng(100 + k), **CLIP_SETTINGS)
        res = lift_sequence(clips["xy"], clips["conf"], clips["k"], prior, cfg, mode="smooth", tracks=clips["tracks"])
        arrays = case_arrays(res.poses_root_relative, res.observed, res.lifted, clips["rel"])
        np.savez(args.cases / f"fold{k}-smooth-clips.npz", group=clips["tracks"], **arrays)
        print(f"fold {k} clips: {int(res.lifted.sum())}/{len(res.lifted)} frames lifted")


def load_cases(folder: Path, mode: str) -> tuple[dict[str, np.ndarray], np.ndarray, np.ndarray, np.ndarray]:
    """Pooled cases of `mode`: arrays by key, and per case its fold, input and group (pose or clip)."""
    pooled: dict[str, list[np.ndarray]] = {}
    fold, kind, group = [], [], []
    for path in sorted(folder.glob(f"fold*-{mode}-*.npz")):
        k = int(path.name[4 : path.name.index("-")])
        with np.load(path) as data:
            for key in data.files:
                if key != "group":
                    pooled.setdefault(key, []).append(data[key])
            n = len(data["group"])
            fold.append(np.full(n, k))
            kind.append(np.full(n, path.stem.rsplit("-", 1)[1]))
            group.append(data["group"])
    if not fold:
        raise SystemExit(f"{folder}: no cases of mode {mode}: run with --lift first")
    return ({k: np.concatenate(v) for k, v in pooled.items()}, np.concatenate(fold), np.concatenate(kind),
            np.concatenate(group))  # fmt: skip


def splits(fold: np.ndarray, group: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """(fit, evaluate) masks: leave one fold out, or with one fold two halves of its groups."""
    folds = np.unique(fold)
    if len(folds) > 1:
        return [(fold != f, fold == f) for f in folds]
    groups = np.unique(group)
    half = np.isin(group, np.random.default_rng(0).permutation(groups)[: len(groups) // 2])
    return [(half, ~half), (~half, half)]


def names_of(cases: dict[str, np.ndarray]) -> list[str]:
    return sorted({k.split("|")[0] for k in cases}, key=lambda n: (n not in SYMMETRY_NAMES, n))


def fit_all(cases: dict[str, np.ndarray], mask: np.ndarray, bins: int) -> dict[str, MeasureModel]:
    return {n: fit_measure(cases[f"{n}|raw"][mask], cases[f"{n}|truth"][mask], circular=n in CIRCULAR_ANGLES,
                           bins=bins) for n in names_of(cases)}  # fmt: skip


def cross_fitted(cases: dict[str, np.ndarray], fold: np.ndarray, kind: np.ndarray, group: np.ndarray,
                 threshold: float, bins: int) -> dict:  # fmt: skip
    """Held-out figures of the calibration, pooled over the cross-fitting splits, per input kind."""
    out: dict = {}
    per: dict[tuple[str, str], dict[str, list]] = {}
    for fit, evaluate in splits(fold, group):
        models = fit_all(cases, fit, bins)
        for n, model in models.items():
            raw, truth = (cases[f"{n}|{x}"][evaluate] for x in ("raw", "truth"))
            ok = np.isfinite(raw) & np.isfinite(truth)
            est = model.estimate(raw[ok])
            for kd in np.unique(kind[evaluate]):
                sel = kind[evaluate][ok] == kd
                d = per.setdefault((n, kd), {"raw": [], "est": [], "truth": [], "low": {}, "high": {}})
                d["raw"].append(raw[ok][sel])
                d["est"].append(est[sel])
                d["truth"].append(truth[ok][sel])
                for lv in LEVELS:
                    lo, hi = model.interval(est[sel], raw[ok][sel], lv)
                    d["low"].setdefault(lv, []).append(lo)
                    d["high"].setdefault(lv, []).append(hi)
    for (n, kd), d in per.items():
        raw, est, truth = (np.concatenate(d[x]) for x in ("raw", "est", "truth"))
        circ = n in CIRCULAR_ANGLES
        row = {"cases": int(len(truth)),
               "mae_raw": float(np.abs(residuals(truth, raw, circ)).mean()),
               "mae_est": float(np.abs(residuals(truth, est, circ)).mean())}  # fmt: skip
        for lv in LEVELS:
            lo, hi = np.concatenate(d["low"][lv]), np.concatenate(d["high"][lv])
            r = residuals(truth, est, circ)
            inside = (r >= lo - est) & (r <= hi - est)
            row[f"coverage_{lv}"] = float(inside.mean())
            row[f"width_{lv}"] = float(np.median(hi - lo))
            if n in SYMMETRY_NAMES:
                lo_c, hi_c = np.clip(lo, 0, 180), np.clip(hi, 0, 180)
                decisive = (hi_c <= threshold) | (lo_c > threshold)
                call_sym = hi_c <= threshold
                agree = call_sym[decisive] == (truth[decisive] <= threshold)
                row[f"decisive_{lv}"] = float(decisive.mean())
                row[f"agreement_{lv}"] = float(agree.mean()) if decisive.any() else float("nan")
        out.setdefault(kd, {})[n] = row
    return out


def clip_median_coverage(cases: dict[str, np.ndarray], fold: np.ndarray, group: np.ndarray, bins: int) -> dict:
    """Per symmetry pair, cross-fitted: how often a clip's median of the true angle lies within the
    median of its frames' 90 % interval ends (the interval `zedo analyze` gives a clip's median)."""
    hits: dict[str, list[bool]] = {}
    for fit, evaluate in splits(fold, group):
        models = fit_all(cases, fit, bins)
        for n in SYMMETRY_NAMES:
            raw, truth = cases[f"{n}|raw"], cases[f"{n}|truth"]
            for g in np.unique(group[evaluate]):
                sel = evaluate & (group == g) & np.isfinite(raw)
                if sel.sum() < 3:
                    continue
                est = models[n].estimate(raw[sel])
                lo, hi = (np.clip(x, 0, 180) for x in models[n].interval(est, raw[sel], 0.9))
                t = np.median(truth[sel])
                hits.setdefault(n, []).append(bool(np.median(lo) <= t <= np.median(hi)))
    return {n: {"clips": len(h), "coverage": float(np.mean(h))} for n, h in hits.items()}


def print_table(figures: dict, mode: str) -> None:
    for kd, rows in figures.items():
        print(f"\n### {mode}, input {kd} (cross-fitted: cases no model saw)")
        print(
            "| measure | cases | MAE raw | MAE estimate | coverage 90 % | median width 90 % | decisive 90 % | agree |"
        )
        print("| --- | --- | --- | --- | --- | --- | --- | --- |")
        for n, r in rows.items():
            dec = f"{100 * r['decisive_0.9']:.0f} % | {100 * r['agreement_0.9']:.0f} %" if n in SYMMETRY_NAMES else "| "
            print(f"| {n} | {r['cases']} | {r['mae_raw']:.1f} | {r['mae_est']:.1f} | "
                  f"{100 * r['coverage_0.9']:.1f} % | {r['width_0.9']:.0f} | {dec} |")  # fmt: skip
        sym = [rows[n] for n in SYMMETRY_NAMES if n in rows]
        if sym:
            print("\nrisk-coverage (symmetry pairs pooled): level | decisive | agreement")
            for lv in LEVELS:
                w = np.array([r["cases"] for r in sym], float)
                dec = np.array([r[f"decisive_{lv}"] for r in sym])
                agr = np.array([r[f"agreement_{lv}"] for r in sym])
                ok = np.isfinite(agr)
                pooled_agree = float((agr[ok] * dec[ok] * w[ok]).sum() / max((dec[ok] * w[ok]).sum(), 1e-9))
                print(f"  {lv:.2f} | {100 * (dec * w).sum() / w.sum():.1f} % | {100 * pooled_agree:.1f} %")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--syrip-dir", required=True)
    ap.add_argument("--folds", type=Path, required=True)
    ap.add_argument("--weights", default="", help="suffix of the fold priors' files (fold<k><weights>.safetensors)")
    ap.add_argument("--cases", type=Path, required=True)
    ap.add_argument("--lift", action="store_true", help="lift the held-out cases first")
    ap.add_argument("--write", action="store_true", help="write the calibrations for the shipped prior")
    ap.add_argument("--out", type=Path, default=None, help="calibration file (default: the package's)")
    ap.add_argument("--threshold", type=float, default=DEFAULT_THRESHOLD_DEG)
    args = ap.parse_args()
    if args.lift:
        lift_cases(args)
    from zedo_cli.lifting.config import DEFAULT_PRESET, calibration_settings, get_preset
    from zedo_cli.prior.weights import load_prior, resolve_prior_path

    shipped = load_prior(resolve_prior_path(None))
    calibrations = []
    for mode in ("none", "smooth"):
        cases, fold, kind, group = load_cases(args.cases, mode)
        bins = BINS[mode]
        figures = cross_fitted(cases, fold, kind, group, args.threshold, bins)
        print_table(figures, mode)
        if mode != "none":
            figures["clip_medians"] = clip_median_coverage(cases, fold, group, bins)
            print("\nclip medians inside the median of the frames' 90 % interval ends:", figures["clip_medians"])
        models = fit_all(cases, np.ones(len(fold), bool), bins)
        provenance = {
            "data": "SyRIP training poses held out of fold priors (benchmarks/folds.py), GT and FiDIP 2D"
            + (", as synthetic 30 fps clips" if mode != "none" else "")
            + "; never Test100 or the synthetic rows",
            "recipe": "benchmarks/calibrate_measures.py",
            "folds": sorted(int(f) for f in np.unique(fold)),
            "cases": int(len(fold)),
            "bins": bins,
            "clips": CLIP_SETTINGS if mode != "none" else None,
            "cross_fitted": {
                kd: {n: {k: round(v, 4) for k, v in r.items()} for n, r in rows.items()} for kd, rows in figures.items()
            },  # fmt: skip
        }
        settings = calibration_settings(get_preset(DEFAULT_PRESET))
        calibrations.append(MeasureCalibration(shipped.sha256, settings, mode, ("pseudo",), shipped.skeleton.joints,
                                               models, provenance))  # fmt: skip
    if args.write:
        out = args.out or bundled_path()
        new = {(c.prior_sha256, c.temporal_mode) for c in calibrations}
        old = read_calibrations(out) if out.exists() else []
        keep = [c for c in old if (c.prior_sha256, c.temporal_mode) not in new]
        write_calibrations(out, keep + calibrations)
        print(f"\nwrote {out}: {len(keep) + len(calibrations)} calibrations")
    else:
        print(json.dumps({c.temporal_mode: {n: m.to_dict() for n, m in list(c.measures.items())[:2]}
                          for c in calibrations}, indent=1))  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
