"""Frame measure intervals whose width grows with the lift's difficulty (its mean reprojection error, px), against
the shipped ones of constant width per bin: locally adaptive (normalised) split-conformal intervals.

On the cases `benchmarks/calibrate/calibrate_measures.py --lift` saved (pseudo camera, each mode), for each
measure: the shipped estimate (`fit_measure`), then per bin the conformal quantiles of the residual divided by
`1 + c d` (d the case's difficulty, c chosen from C_GRID on the fit cases for the narrowest median 90 % interval),
the interval `estimate +- q (1 + c d)`. Scored like the recipe: cross-fitted over the folds per source and tercile
of the difficulty, and each source with a fit on the other only; the median width beside each coverage.

    python experiments/difficulty_scaled_intervals.py --cases cases/
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root
from benchmarks.calibrate.calibrate_measures import (
    BINS,
    CIRCULAR_ANGLES,
    DIFFICULTY,
    MODES,
    difficulty_terciles,
    load_cases,
    names_of,
    source_of,
    splits,
)
from zedo_cli.analysis.uncertainty.calibration import fit_measure, residuals
from zedo_cli.stats import conformal_quantile

C_GRID = (0.0, 0.05, 0.1, 0.2, 0.4, 0.8)  # per px of mean reprojection error
LEVEL = 0.9


def scaled_fit(raw: np.ndarray, truth: np.ndarray, d: np.ndarray, circular: bool, bins: int) -> dict:
    """The shipped estimate and, per bin, the quantiles of the residual over `1 + c d` for the c of C_GRID with
    the narrowest median interval on these cases (c = 0: the shipped intervals)."""
    model = fit_measure(raw, truth, circular=circular, bins=bins)
    ok = np.isfinite(raw) & np.isfinite(truth) & np.isfinite(d)
    r = residuals(truth[ok], model.estimate(raw[ok]), circular)
    b = model.bins(raw[ok])
    best = None
    for c in C_GRID:
        scale = 1.0 + c * d[ok]
        q = [(conformal_quantile(-r[b == k] / scale[b == k], (1 + LEVEL) / 2),
              conformal_quantile(r[b == k] / scale[b == k], (1 + LEVEL) / 2)) for k in range(bins)]  # fmt: skip
        width = float(np.median(np.array([lo + hi for lo, hi in q])[b] * scale))
        if best is None or width < best["width"]:
            best = {"model": model, "c": c, "q": q, "width": width}
    return best


def score(fits: dict, cases: dict[str, np.ndarray], mask: np.ndarray) -> tuple[int, int, list[float]]:
    """(cases inside, cases, widths) of the scaled intervals of `fits` on the cases of `mask`."""
    inside, count, widths = 0, 0, []
    d = cases[DIFFICULTY]
    for name, f in fits.items():
        raw, truth = cases[f"{name}|raw"], cases[f"{name}|truth"]
        ok = mask & np.isfinite(raw) & np.isfinite(truth) & np.isfinite(d)
        est = f["model"].estimate(raw[ok])
        r = residuals(truth[ok], est, name in CIRCULAR_ANGLES)
        b = f["model"].bins(raw[ok])
        scale = 1.0 + f["c"] * d[ok]
        q = np.array(f["q"])  # (bins, 2): low and high arm
        low, high = q[b, 0] * scale, q[b, 1] * scale
        inside += int(((r >= -low) & (r <= high)).sum())
        count += int(ok.sum())
        widths += (low + high).tolist()
    return inside, count, widths


def fit_all_scaled(cases: dict[str, np.ndarray], mask: np.ndarray, bins: int, scaled: bool) -> dict:
    d = cases[DIFFICULTY] if scaled else np.zeros(len(mask))
    out = {}
    for n in names_of(cases):
        f = scaled_fit(cases[f"{n}|raw"][mask], cases[f"{n}|truth"][mask], d[mask], n in CIRCULAR_ANGLES, bins)
        if not scaled:
            f["c"] = 0.0
        out[n] = f
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", type=Path, required=True)
    args = ap.parse_args()
    for mode in MODES:
        cases, fold, kind, group = load_cases(args.cases, mode)
        if DIFFICULTY not in cases:
            raise SystemExit(f"{args.cases}: no difficulty saved: rerun calibrate_measures.py --lift")
        src, third = source_of(kind), difficulty_terciles(cases, kind)
        print(
            f"\n## {mode}\n\n| held out | cases | shipped: coverage (median width) | scaled: coverage (median width) |"
        )
        print("| --- | --- | --- | --- |")
        rows: dict[str, list[str]] = {}
        for scaled in (False, True):
            held = [(fit_all_scaled(cases, fit, BINS[mode], scaled), ev) for fit, ev in splits(fold, group)]
            for label in np.unique(third[np.isfinite(cases[DIFFICULTY])]):
                inside, count, widths = 0, 0, []
                for fits, ev in held:
                    i, c, w = score(fits, cases, ev & (third == label))
                    inside, count, widths = inside + i, count + c, widths + w
                rows.setdefault(f"folds, {label}", [str(count)]).append(
                    f"{100 * inside / max(count, 1):.1f} % ({np.median(widths):.0f})"
                )
            for s in np.unique(src):
                fits = fit_all_scaled(cases, src != s, BINS[mode], scaled)
                i, c, w = score(fits, cases, src == s)
                rows.setdefault(f"{s} left out", [str(c)]).append(f"{100 * i / max(c, 1):.1f} % ({np.median(w):.0f})")
        for label, cells in rows.items():
            print(f"| {label} | " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
