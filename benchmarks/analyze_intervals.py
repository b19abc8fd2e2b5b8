"""Coverage of zedo analyze's 90 % intervals when the per-joint radii are right.

The truth: the SyRIP Test100 weak-ground-truth 3D poses (syrip12, metres). For each noise
level sigma, `--repeats` noisy copies of every pose are made (independent isotropic Gaussian
joint errors of sigma per axis: the error model the intervals assume) and given the radius
uncertainty_m = 2.5003 sigma (the true 90 % ball). The intervals of `analysis.uncertainty`
are computed around each noisy pose, and the share that holds the measure of the true pose is
reported per symmetry pair, for zedo's interval (the percentile interval and its reflection
about the reported value, together) and, for comparison, for the plain percentile interval;
also the mean width and the share of true calls at 28 degrees kept (equal, or "uncertain").

    .venv/bin/python benchmarks/analyze_intervals.py --syrip-dir ../shared/data/syrip
"""

from __future__ import annotations

import argparse

import numpy as np

from zedo_cli.analysis.analyse import measure_ranges
from zedo_cli.analysis.symmetry import PAIRS, measure_name, symmetry_angles, symmetry_call
from zedo_cli.analysis.uncertainty import CHI3_Q90, sample_intervals
from zedo_cli.data.datasets import load_syrip_3d


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--syrip-dir", required=True)
    ap.add_argument("--sigmas-mm", type=float, nargs="+", default=[4.0, 8.0, 16.0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--samples", type=int, default=1000)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    truth = load_syrip_3d(args.syrip_dir, "test")
    skel = truth.skeleton
    rng = np.random.default_rng(args.seed)
    names = [measure_name(p) for p in PAIRS]
    true = symmetry_angles(truth.poses, skel)
    ranges = measure_ranges()
    print("| sigma (mm) | radius (mm) | pair | coverage, zedo | coverage, percentile only | "
          "mean width (deg) | true call kept or uncertain |")  # fmt: skip
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for sigma_mm in args.sigmas_mm:
        sigma = sigma_mm / 1000.0
        poses = np.concatenate([truth.poses] * args.repeats)
        noisy = poses + rng.normal(0.0, sigma, poses.shape)
        radii = np.full(noisy.shape[:2], sigma * CHI3_Q90)
        f = lambda p: symmetry_angles(p, skel)  # noqa: E731
        intervals = sample_intervals(noisy, radii, f, ranges=ranges, samples=args.samples, seed=args.seed)
        reported = f(noisy)
        for name in names:
            t = np.concatenate([true[name]] * args.repeats)
            low, high = intervals[name]
            cov = ((low <= t) & (t <= high)).mean()
            p_low, p_high = _percentile(noisy, radii, f, name, args.samples, args.seed)
            pcov = ((p_low <= t) & (t <= p_high)).mean()
            kept = np.mean([
                symmetry_call(v, 28.0, lo, hi) in (symmetry_call(tv, 28.0), "uncertain")
                for v, lo, hi, tv in zip(reported[name], low, high, t, strict=True)
            ])  # fmt: skip
            pair = name.removeprefix("symmetry_").removesuffix("_deg").replace("_", " ")
            print(f"| {sigma_mm:g} | {sigma_mm * CHI3_Q90:.0f} | {pair} | {100 * cov:.0f} % | {100 * pcov:.0f} % | "
                  f"{np.mean(high - low):.1f} | {100 * kept:.0f} % |")  # fmt: skip


def _percentile(noisy: np.ndarray, radii: np.ndarray, f, name: str, samples: int, seed: int):  # noqa: ANN001, ANN202
    """The plain percentile interval [q5, q95] of the same sampling (for comparison only)."""
    rng = np.random.default_rng(seed)
    lows, highs = [], []
    per = max(1, 200_000 // samples)
    for start in range(0, len(noisy), per):
        p, r = noisy[start : start + per], radii[start : start + per] / CHI3_Q90
        draws = p[None] + rng.standard_normal((samples, *p.shape)) * r[None, ..., None]
        v = f(draws.reshape(-1, *p.shape[1:]))[name].reshape(samples, len(p))
        q5, q95 = np.percentile(v, [5.0, 95.0], axis=0)
        lows.append(q5)
        highs.append(q95)
    return np.concatenate(lows), np.concatenate(highs)


if __name__ == "__main__":
    main()
