"""Temporal mode vs frame-by-frame lifting, on synthetic infant videos made from real SyRIP poses.

There is no real infant video with 3D truth here, so each sequence is built from the SyRIP
Test100 3D poses (syrip12, hip-centred, metres): `--keyposes` random poses, eased (cosine)
from one to the next over `--transition-s` seconds at `--fps`, turned slowly about the vertical
and the optical axis and drifting in translation, placed about 1 m in front of the pseudo
camera (f = 2000 px, principal point at the centre of a 1280x720 image), projected exactly,
then given detector-like noise: Gaussian pixel noise of `--noise-px`, joints dropped with
probability `--drop`, and one short gap of frames with only two joints (not liftable).

Every candidate lifts the same 2D with the bundled prior and `--preset`; reported over the
lifted frames: MPJPE and PA-MPJPE (mm, root-relative), the acceleration error (mean over
joints and frame triples of |second difference of the prediction - the truth's|, mm/frame^2),
the mean |second difference| itself (the truth's is printed below the table), the mean
reprojection error of the observed joints (px) and poses per second (lifted frames / wall time).

    .venv/bin/python benchmarks/accuracy/temporal.py --syrip-dir ../shared/data/syrip --seed 0
"""

from __future__ import annotations

import argparse
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import torch

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the repository root
from zedo_cli.data.datasets import load_syrip_3d
from zedo_cli.evaluation.clips.eased import make_sequences
from zedo_cli.evaluation.metrics import mpjpe_mm, pa_mpjpe_mm
from zedo_cli.lifting.config import LiftConfig, get_preset
from zedo_cli.lifting.solver import LiftResult
from zedo_cli.lifting.temporal import lift_sequence, smooth_tracks_2d
from zedo_cli.prior.weights import load_prior, resolve_prior_path


def accel_mm(poses: np.ndarray, tracks: np.ndarray, lifted: np.ndarray) -> np.ndarray:
    """Second differences `(M, J, 3)` in mm over the frame triples of one track that are all lifted."""
    out = []
    for tr in np.unique(tracks):
        idx = np.flatnonzero(tracks == tr)
        p, ok = poses[idx], lifted[idx]
        valid = ok[:-2] & ok[1:-1] & ok[2:]
        out.append(1000.0 * (p[:-2] - 2 * p[1:-1] + p[2:])[valid])
    return np.concatenate(out)


def score(name: str, res: LiftResult, data: dict[str, np.ndarray], seconds: float) -> dict[str, float | str]:
    ok = res.lifted
    pred, truth = res.poses_root_relative, data["rel"]
    acc_p, acc_t = accel_mm(pred, data["tracks"], ok), accel_mm(truth, data["tracks"], ok)
    return {
        "mode": name,
        "mpjpe": mpjpe_mm(pred[ok], truth[ok]),
        "pa": pa_mpjpe_mm(pred[ok], truth[ok]),
        "accel_err": float(np.linalg.norm(acc_p - acc_t, axis=-1).mean()),
        "accel": float(np.linalg.norm(acc_p, axis=-1).mean()),
        "truth_accel": float(np.linalg.norm(acc_t, axis=-1).mean()),
        "reproj": float(np.nanmean(res.reprojection_error_px[ok])),
        "pps": float(ok.sum() / seconds),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--syrip-dir", required=True)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--sequences", type=int, default=4)
    ap.add_argument("--keyposes", type=int, default=4)
    ap.add_argument("--transition-s", type=float, default=1.0)
    ap.add_argument("--fps", type=float, default=30.0)
    ap.add_argument("--noise-px", type=float, default=3.0)
    ap.add_argument("--drop", type=float, default=0.03)
    ap.add_argument("--gap", type=int, default=3, help="frames of each sequence's unliftable gap")
    ap.add_argument("--preset", default="fast")
    ap.add_argument("--sigma", type=float, nargs="+", default=[2.0], help="filter widths (frames) to try")
    ap.add_argument("--warm-steps", type=int, nargs="+", default=[None], help="warm_steps to try (default: preset's)")
    ap.add_argument("--warm-t-start", type=float, nargs="+", default=[None])
    ap.add_argument("--warm-release", type=float, nargs="+", default=[None], help="warm_release_fraction to try")
    ap.add_argument(
        "--modes",
        nargs="+",
        default=["none", "2d-smooth", "smooth", "two-pass"],
        help="lift_sequence modes, and 2d-smooth: the detections smoothed, then frame-by-frame",
    )
    args = ap.parse_args()

    rng = np.random.default_rng(args.seed)
    data = make_sequences(load_syrip_3d(args.syrip_dir, "test").poses, rng, count=args.sequences,
                          keyposes=args.keyposes, transition_s=args.transition_s, fps=args.fps,
                          noise_px=args.noise_px, drop=args.drop, gap=args.gap)  # fmt: skip
    prior = load_prior(resolve_prior_path(None))
    base = get_preset(args.preset)
    torch.manual_seed(args.seed)
    print(f"seed {args.seed}: {args.sequences} sequences, {len(data['xy'])} frames at {args.fps:g} fps, "
          f"noise {args.noise_px:g} px, drop {args.drop:g}, preset {args.preset}, "
          f"torch threads {torch.get_num_threads()}")  # fmt: skip
    rows = []
    xy, conf, k, tracks = data["xy"], data["conf"], data["k"], data["tracks"]
    lift_sequence(xy[:8], conf[:8], k[:8], prior, base, mode="none")  # warm-up: the first call is slower

    def run(name: str, mode: str, cfg: LiftConfig, sigma: float = 0.0, inputs: tuple | None = None) -> None:
        t0 = time.perf_counter()
        res = lift_sequence(*(inputs or (xy, conf, k)), prior, cfg, mode=mode, sigma=sigma, tracks=tracks)
        rows.append(score(name, res, data, time.perf_counter() - t0))

    for mode in args.modes:
        warm = mode == "two-pass"
        for sigma in args.sigma if mode != "none" else [None]:
            grid = [(a, b, c) for a in args.warm_steps for b in args.warm_t_start for c in args.warm_release]
            for ws, wt, wr in grid:
                cfg = base
                cfg = replace(cfg, warm_steps=ws) if ws is not None else cfg
                cfg = replace(cfg, warm_t_start=wt) if wt is not None else cfg
                cfg = replace(cfg, warm_release_fraction=wr) if wr is not None else cfg
                label = mode + (f" sigma={sigma:g}" if sigma is not None else "")
                if warm:
                    label += f" ({cfg.warm_steps} steps, t={cfg.warm_t_start:g}, release {cfg.warm_release_fraction:g})"
                if mode == "2d-smooth":
                    xy_s = smooth_tracks_2d(xy, sigma, tracks)
                    run(label, "none", cfg, inputs=(xy_s, conf, k))
                else:
                    run(label, mode, cfg, sigma=sigma if sigma is not None else 0.0)
                if not warm:
                    break
    print(
        f"truth's mean |second difference|: {rows[0]['truth_accel']:.2f} mm/frame^2; "
        f"{int(np.isnan(data['xy']).all(-1).sum())} joints dropped"
    )
    print("| mode | MPJPE (mm) | PA-MPJPE (mm) | accel. error (mm/frame^2) | mean accel. | reproj. (px) | poses/s |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for r in rows:
        print(
            f"| {r['mode']} | {r['mpjpe']:.1f} | {r['pa']:.1f} | {r['accel_err']:.2f} | {r['accel']:.2f} | "
            f"{r['reproj']:.2f} | {r['pps']:.0f} |"
        )


if __name__ == "__main__":
    main()
