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

    .venv/bin/python benchmarks/temporal.py --syrip-dir ../shared/data/syrip --seed 0
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable
from dataclasses import replace

import numpy as np
import torch

from zedo_cli.data.datasets import load_syrip_3d
from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.evaluation.metrics import mpjpe_mm, pa_mpjpe_mm
from zedo_cli.lifting.camera import Intrinsics, project
from zedo_cli.lifting.config import LiftConfig, get_preset
from zedo_cli.lifting.solver import LiftResult
from zedo_cli.lifting.temporal import lift_sequence, smooth_tracks_2d
from zedo_cli.prior.weights import load_prior, resolve_prior_path

IMAGE_W, IMAGE_H = 1280, 720
SYRIP12_JOINTS = get_skeleton("syrip12").joints


def _rotation(yaw: np.ndarray, roll: np.ndarray) -> np.ndarray:
    """Rotations `(T, 3, 3)`: about the camera's vertical axis (y) by `yaw`, then the optical axis (z) by `roll`."""
    cy, sy, cr, sr = np.cos(yaw), np.sin(yaw), np.cos(roll), np.sin(roll)
    ry = np.zeros((len(yaw), 3, 3))
    ry[:, 0, 0], ry[:, 0, 2], ry[:, 1, 1], ry[:, 2, 0], ry[:, 2, 2] = cy, sy, 1.0, -sy, cy
    rz = np.zeros((len(roll), 3, 3))
    rz[:, 0, 0], rz[:, 0, 1], rz[:, 1, 0], rz[:, 1, 1], rz[:, 2, 2] = cr, -sr, sr, cr, 1.0
    return rz @ ry


# A camera placement for one synthetic clip: (rng, root-relative camera-frame poses (T, J, 3), their
# root's drift (T, 3) about its mean) -> (K (3, 3), root points (T, 3) in the camera frame).
Placement = Callable[[np.random.Generator, np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]


def scale_2d(xy: np.ndarray) -> np.ndarray:
    """The size of 2D poses `(..., J, 2)` in pixels `(...,)`: the RMS distance of the known joints from their mean."""
    known = np.isfinite(xy).all(-1)  # (..., J)
    count = known.sum(-1, keepdims=True)  # a pose without a known joint has no size (NaN)
    with np.errstate(invalid="ignore", divide="ignore"):
        c = np.where(known[..., None], xy, 0.0).sum(-2, keepdims=True) / count[..., None]
        d2 = np.where(known, ((xy - c) ** 2).sum(-1), 0.0)
        return np.sqrt(d2.sum(-1) / count[..., 0])


def _eased_error(e0: np.ndarray, e1: np.ndarray, ease: np.ndarray) -> np.ndarray:
    """A detector's relative error `(T, J, 2)` eased from key pose e0 `(J, 2)` to e1; a joint missed at
    the nearer key pose is missed (NaN)."""
    mix = (1 - ease)[:, None, None] * np.nan_to_num(e0) + ease[:, None, None] * np.nan_to_num(e1)
    missed = np.where(ease[:, None] < 0.5, np.isnan(e0).any(-1), np.isnan(e1).any(-1))  # (T, J)
    mix[missed] = np.nan
    return mix


# The syrip12 joints as a tree for `interpolation="segments"`: (parent, child); "root" is the hips' midpoint,
# "neck" the shoulders' midpoint (the two halves of each girdle stay opposite, so those midpoints stay).
_SEGMENTS = (("root", "left_hip"), ("root", "right_hip"), ("root", "neck"), ("neck", "left_shoulder"),
             ("neck", "right_shoulder"), ("left_hip", "left_knee"), ("left_knee", "left_ankle"),
             ("right_hip", "right_knee"), ("right_knee", "right_ankle"), ("left_shoulder", "left_elbow"),
             ("left_elbow", "left_wrist"), ("right_shoulder", "right_elbow"),
             ("right_elbow", "right_wrist"))  # fmt: skip


def _segment_vectors(poses: np.ndarray, joints: tuple[str, ...]) -> np.ndarray:
    """`(P, S, 3)` parent-to-child vectors of `_SEGMENTS` of syrip12 poses `(P, J, 3)`."""
    at = {n: poses[:, i] for i, n in enumerate(joints)}
    at["root"] = (at["left_hip"] + at["right_hip"]) / 2
    at["neck"] = (at["left_shoulder"] + at["right_shoulder"]) / 2
    return np.stack([at[c] - at[p] for p, c in _SEGMENTS], 1)


def _slerp(a: np.ndarray, b: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Unit directions `(T, S, 3)` turned from unit `a (S, 3)` to unit `b` along great circles, fraction `t (T,)`."""
    theta = np.arccos(np.clip((a * b).sum(-1), -1.0, 1.0))  # (S,)
    sin = np.sin(theta)
    turns = sin > 1e-9  # (S,) else (nearly) the same direction: a straight mix
    safe = np.where(turns, sin, 1.0)
    wa = np.where(turns, np.sin((1 - t)[:, None] * theta) / safe, (1 - t)[:, None])  # (T, S)
    wb = np.where(turns, np.sin(t[:, None] * theta) / safe, t[:, None])
    out = wa[..., None] * a + wb[..., None] * b
    return out / np.linalg.norm(out, axis=-1, keepdims=True)


def segment_interpolation(keys: np.ndarray, ease: np.ndarray, joints: tuple[str, ...]) -> np.ndarray:
    """Root-relative poses `((K - 1) * T, J, 3)` from syrip12 key poses `(K, J, 3)` that keep one infant's
    bones: every segment keeps its length in the first key pose and turns, at `ease (T,)`, along a great
    circle from one key pose's direction to the next. (Easing the joints' positions instead shortens a
    turning bone: half-way through a 90 degree turn to 71 % of its length.)"""
    vec = _segment_vectors(keys, joints)  # (K, S, 3)
    length = np.linalg.norm(vec[0], axis=-1)  # (S,) the clip's infant
    unit = vec / np.linalg.norm(vec, axis=-1, keepdims=True)
    dirs = np.concatenate([_slerp(unit[i], unit[i + 1], ease) for i in range(len(keys) - 1)])  # (N, S, 3)
    seg = dirs * length[:, None]
    out = {"root": np.zeros((len(seg), 3))}
    for s, (parent, child) in enumerate(_SEGMENTS):  # every parent comes before its children
        out[child] = out[parent] + seg[:, s]
    return np.stack([out[n] for n in joints], 1)


def make_sequences(
    poses: np.ndarray, rng: np.random.Generator, *, count: int, keyposes: int, transition_s: float, fps: float,
    noise_px: float, drop: float, gap: int, place: Placement | None = None, key_noise: np.ndarray | None = None,
    noise_rel: float = 0.0, depth_m: float = 1.0, drift_scale: float = 1.0, interpolation: str = "positions",
) -> dict[str, np.ndarray]:  # fmt: skip
    """Synthetic videos: truth (root-relative and camera frame), noisy 2D, confidences, track labels.

    By default about 1 m in front of the pseudo camera. `place` puts each clip before another camera
    (its K and root points; the root drifts up to 2 cm/s about its place there). `key_noise (P, J, 2)`:
    a detector's error of each pose of `poses`, relative to the pose's 2D size (`scale_2d`; NaN: the
    joint was missed), eased from key pose to key pose like the poses and scaled to each frame's 2D
    size. `noise_rel`: Gaussian pixel noise as a fraction of the frame's 2D size, on top of `noise_px`.

    `depth_m` and `drift_scale` place the body before the pseudo camera: about `depth_m` in front of it,
    its random offset and drift scaled by `drift_scale`. The defaults (1 m, 1) are the calibration clips'
    geometry (benchmarks/calibrate_measures.py), which overfills a 1280x720 frame; the demo clip
    (benchmarks/demo_clip.py) stands further back and drifts less, to stay inside it. The random
    draws are the same whatever the two values.

    `interpolation`: "positions" eases every joint's position from key pose to key pose (the clips every
    shipped calibration except the `3d_` clip features' was fitted on): a turning bone shortens half-way,
    in the calibration clips thighs to a median 79 % of their key poses' length and in 5 % of frames below
    27 %. "segments" keeps the first key pose's bone lengths through the clip and turns each segment
    (`segment_interpolation`), as a real infant's limbs move. The random draws are the same for both."""
    frames = int(round(transition_s * fps))
    rel_all, cam_all, tracks, k_all, err_all = [], [], [], [], []
    for track in range(count):
        picked = rng.choice(len(poses), keyposes, replace=False)
        keys = poses[picked]
        u = np.arange(frames) / frames
        ease = (1.0 - np.cos(np.pi * u)) / 2.0  # zero velocity at every key pose: smooth motion
        if interpolation == "segments":
            seq = segment_interpolation(keys, ease, SYRIP12_JOINTS)
        else:
            seq = np.concatenate([(1 - ease)[:, None, None] * keys[i] + ease[:, None, None] * keys[i + 1]
                                  for i in range(keyposes - 1)])  # fmt: skip
        if key_noise is not None:
            err_all.append(np.concatenate([_eased_error(key_noise[picked[i]], key_noise[picked[i + 1]], ease)
                                           for i in range(keyposes - 1)]))  # fmt: skip
        t = np.arange(len(seq)) / fps
        yaw = rng.uniform(-0.4, 0.4) + rng.uniform(-0.3, 0.3) * t  # up to ~17 deg/s
        roll = rng.uniform(-0.2, 0.2) + rng.uniform(-0.1, 0.1) * t
        rel = seq @ _rotation(yaw, roll).transpose(0, 2, 1)
        if place is None:
            offset, drift = rng.normal(0, [0.05, 0.05, 0.1]), rng.uniform(-0.05, 0.05, 3)
            root = np.array([0.0, 0.0, depth_m]) + drift_scale * offset + drift_scale * drift * t[:, None]
            k_all.append(np.repeat(Intrinsics.pseudo(IMAGE_W, IMAGE_H).matrix()[None], len(seq), 0))
        else:
            kmat, root = place(rng, rel, rng.uniform(-0.02, 0.02, 3) * (t - t.mean())[:, None])
            k_all.append(np.repeat(kmat[None], len(seq), 0))
        rel_all.append(rel)
        cam_all.append(rel + root[:, None])
        tracks.append(np.full(len(seq), track))
    rel, cam, track, k = np.concatenate(rel_all), np.concatenate(cam_all), np.concatenate(tracks), np.concatenate(k_all)
    xy = project(torch.tensor(cam), torch.tensor(k)).numpy()
    size = scale_2d(xy)[:, None, None]  # (T, 1, 1) px
    if key_noise is not None:
        xy = xy + np.concatenate(err_all) * size  # NaN (a missed joint) stays NaN: confidence 0 below
    xy = xy + rng.normal(0.0, noise_px, cam.shape[:2] + (2,))
    if noise_rel:
        xy = xy + rng.normal(0.0, 1.0, cam.shape[:2] + (2,)) * noise_rel * size
    conf = np.where(np.isfinite(xy).all(-1), 1.0, 0.0)
    conf[rng.random(conf.shape) < drop] = 0.0
    for tr in range(count):  # one short gap per sequence: two joints only, not liftable
        idx = np.flatnonzero(track == tr)
        at = rng.integers(10, len(idx) - 10 - gap)
        conf[idx[at : at + gap], 2:] = 0.0
    xy[conf == 0] = np.nan
    return {"rel": rel, "cam": cam, "xy": xy, "conf": conf, "k": k, "tracks": track}


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
