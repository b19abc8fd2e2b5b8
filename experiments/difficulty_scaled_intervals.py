"""Frame measure intervals whose width grows with the lift's difficulty, against the shipped ones of constant width
per bin: locally adaptive (normalised) split-conformal intervals. Two difficulties: the lift's mean reprojection
error (px, per case), and the foreshortening of the measure's own bones in the lifted pose (per case and measure: the
largest |dz| / |d| over the bones between the joints the measure uses, 0 in the image plane, 1 along the axis).

On the cases `benchmarks/calibrate/calibrate_measures.py --lift` saved (pseudo camera, each mode), for each
measure: the shipped estimate (`fit_measure`), then per bin the conformal quantiles of the residual divided by
`1 + c d` (d the case's difficulty, c chosen from C_GRID on the fit cases for the narrowest median 90 % interval),
the interval `estimate +- q (1 + c d)`. Scored like the recipe: cross-fitted over the folds per source and tercile
of the difficulty, and each source with a fit on the other only; the median width beside each coverage.

    python experiments/difficulty_scaled_intervals.py --cases cases/ [--difficulty foreshortening]
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
    LIFTED,
    MODES,
    SKELETON,
    difficulty_terciles,
    load_cases,
    measures,
    names_of,
    source_of,
    splits,
)
from zedo_cli.analysis.uncertainty.calibration import fit_measure, measure_joints, residuals
from zedo_cli.stats import conformal_quantile

C_GRID = {
    "reprojection": (0.0, 0.05, 0.1, 0.2, 0.4, 0.8),  # per px of mean reprojection error
    "foreshortening": (0.0, 0.5, 1.0, 2.0, 4.0),
}  # per unit of |dz| / |d|
LEVEL = 0.9


def foreshortening(lifted: np.ndarray, uses: np.ndarray) -> np.ndarray:
    """Per case `(n,)`: the largest |dz| / |d| over the skeleton's bones between joints of `uses (J,)` in the
    lifted poses `(n, J, 3)` (camera axes); NaN where the pose was not lifted."""
    out = np.zeros(len(lifted))
    for a, b in SKELETON.bones:
        if uses[a] and uses[b]:
            bone = lifted[:, b] - lifted[:, a]
            out = np.maximum(out, np.abs(bone[:, 2]) / np.maximum(np.linalg.norm(bone, axis=-1), 1e-9))
    return np.where(np.isfinite(lifted).all((1, 2)), out, np.nan)


def difficulties(cases: dict[str, np.ndarray], kind: str) -> dict[str, np.ndarray]:
    """Per measure, each case's difficulty of `kind` (reprojection: the same for every measure)."""
    if kind == "reprojection":
        return {n: cases[DIFFICULTY] for n in names_of(cases)}
    if LIFTED not in cases:
        raise SystemExit("no lifted poses saved with the cases: rerun calibrate_measures.py --lift")
    uses = measure_joints(SKELETON, measures, names_of(cases))
    return {n: foreshortening(cases[LIFTED], uses[n]) for n in names_of(cases)}


def scaled_fit(raw: np.ndarray, truth: np.ndarray, d: np.ndarray, circular: bool, bins: int,
               grid: tuple[float, ...]) -> dict:  # fmt: skip
    """The shipped estimate and, per bin, the quantiles of the residual over `1 + c d` for the c of C_GRID with
    the narrowest median interval on these cases (c = 0: the shipped intervals)."""
    model = fit_measure(raw, truth, circular=circular, bins=bins)
    ok = np.isfinite(raw) & np.isfinite(truth) & np.isfinite(d)
    r = residuals(truth[ok], model.estimate(raw[ok]), circular)
    b = model.bins(raw[ok])
    best = None
    for c in grid:
        scale = 1.0 + c * d[ok]
        q = [(conformal_quantile(-r[b == k] / scale[b == k], (1 + LEVEL) / 2),
              conformal_quantile(r[b == k] / scale[b == k], (1 + LEVEL) / 2)) for k in range(bins)]  # fmt: skip
        width = float(np.median(np.array([lo + hi for lo, hi in q])[b] * scale))
        if best is None or width < best["width"]:
            best = {"model": model, "c": c, "q": q, "width": width}
    return best


def score(fits: dict, cases: dict[str, np.ndarray], hard: dict[str, np.ndarray], mask: np.ndarray
          ) -> tuple[int, int, list[float]]:  # fmt: skip
    """(cases inside, cases, widths) of the scaled intervals of `fits` on the cases of `mask`."""
    inside, count, widths = 0, 0, []
    for name, f in fits.items():
        raw, truth, d = cases[f"{name}|raw"], cases[f"{name}|truth"], hard[name]
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


def fit_all_scaled(cases: dict[str, np.ndarray], hard: dict[str, np.ndarray], mask: np.ndarray, bins: int,
                   grid: tuple[float, ...], scaled: bool) -> dict:  # fmt: skip
    out = {}
    for n in names_of(cases):
        d = hard[n][mask] if scaled else np.zeros(int(mask.sum()))
        f = scaled_fit(cases[f"{n}|raw"][mask], cases[f"{n}|truth"][mask], d, n in CIRCULAR_ANGLES, bins, grid)
        if not scaled:
            f["c"] = 0.0
        out[n] = f
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", type=Path, required=True)
    ap.add_argument("--difficulty", choices=tuple(C_GRID), default="reprojection")
    args = ap.parse_args()
    grid = C_GRID[args.difficulty]
    for mode in MODES:
        cases, fold, kind, group = load_cases(args.cases, mode)
        if DIFFICULTY not in cases:
            raise SystemExit(f"{args.cases}: no difficulty saved: rerun calibrate_measures.py --lift")
        src, third, hard = source_of(kind), difficulty_terciles(cases, kind), difficulties(cases, args.difficulty)
        print(
            f"\n## {mode}\n\n| held out | cases | shipped: coverage (median width) | scaled: coverage (median width) |"
        )
        print("| --- | --- | --- | --- |")
        rows: dict[str, list[str]] = {}
        for scaled in (False, True):
            held = [(fit_all_scaled(cases, hard, fit, BINS[mode], grid, scaled), ev) for fit, ev in splits(fold, group)]
            for label in np.unique(third[np.isfinite(cases[DIFFICULTY])]):
                inside, count, widths = 0, 0, []
                for fits, ev in held:
                    i, c, w = score(fits, cases, hard, ev & (third == label))
                    inside, count, widths = inside + i, count + c, widths + w
                rows.setdefault(f"folds, {label}", [str(count)]).append(
                    f"{100 * inside / max(count, 1):.1f} % ({np.median(widths):.0f})"
                )
            for s in np.unique(src):
                fits = fit_all_scaled(cases, hard, src != s, BINS[mode], grid, scaled)
                i, c, w = score(fits, cases, hard, src == s)
                rows.setdefault(f"{s} left out", [str(c)]).append(f"{100 * i / max(c, 1):.1f} % ({np.median(w):.0f})")
        for label, cells in rows.items():
            print(f"| {label} | " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
