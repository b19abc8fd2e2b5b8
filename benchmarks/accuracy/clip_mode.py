"""`--temporal clip` against the other temporal modes on clips of one infant each, per source.

Sources: `syrip` (SyRIP poses, one infant's bones kept and each segment turned from key pose to key pose,
`make_sequences(interpolation="segments")`; `--split test` for Test100, the final check, else the training poses;
`--supine`: each pose first turned chest to the camera, head up the image, and the body swaying about one place,
as infants are filmed) and `adult` (the
adult motion capture made infant-like, `zedo_cli.evaluation.clips`, when it is installed with the data). Each clip
is seen through a camera of f = 1000 px (known, `--camera known`) or the pseudo camera (`--camera pseudo`), 3 px
detector noise, 3 % of joints dropped. Scored against the 3D truth, pelvis-centred without scale or rotation
alignment, over the frames every mode lifted: bone-length CV (the eight limb bones' coefficient of variation within
a clip, averaged), MPJPE (mm), elbow/knee interior-angle MAE (deg), MPJVE (mm/s, the velocity error of root-relative
joints), mean reprojection error (px); and for clip mode the skeleton's bone ratios against the truth, its 90 %
intervals' coverage (known camera), the depth side of segments over 30 degrees out of the image plane in frames not
flagged, and the share of limb-frames flagged.

    .venv/bin/python benchmarks/accuracy/clip_mode.py --syrip-dir ../shared/data/syrip --clips 8
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from zedo_cli.analysis.pose.geometry import angle_between_deg
from zedo_cli.analysis.pose.joint_angles import joint_angles
from zedo_cli.data.datasets import load_syrip_3d
from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.evaluation.clips.cameras import Sway, turned_supine
from zedo_cli.evaluation.clips.eased import IMAGE_H, IMAGE_W, make_sequences
from zedo_cli.lifting.camera import Intrinsics
from zedo_cli.lifting.clip import BONE_NAMES, LIMB_BONES
from zedo_cli.lifting.config import get_preset
from zedo_cli.lifting.temporal import lift_sequence
from zedo_cli.prior.weights import load_prior, resolve_prior_path
from zedo_cli.stats import conformal_quantile

SKELETON = get_skeleton("syrip12")
MODES = ("none", "smooth", "two-pass", "clip")
FPS = 30.0


def known_camera(focal: float):  # noqa: ANN201
    def place(rng: np.random.Generator, rel: np.ndarray, drift: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        k = Intrinsics(focal, focal, IMAGE_W / 2, IMAGE_H / 2, "cli").matrix()
        root = np.array([0.0, 0.0, 1.0]) + rng.normal(0, [0.03, 0.03, 0.05]) + drift
        return k, root

    return place


def bone_cv(poses: np.ndarray) -> float:
    """Mean over the eight limb bones of their coefficient of variation within the clip (%)."""
    cvs = []
    for a, b in LIMB_BONES:
        length = np.linalg.norm(poses[:, SKELETON.index(a)] - poses[:, SKELETON.index(b)], axis=-1)
        length = length[np.isfinite(length)]
        cvs.append(length.std() / length.mean())
    return 100 * float(np.mean(cvs))


def interior_angles(poses: np.ndarray) -> np.ndarray:
    """Elbow and knee interior angles `(T, 4)` in degrees (180 = straight)."""
    out = []
    for a, b, c in (
        ("left_hip", "left_knee", "left_ankle"),
        ("right_hip", "right_knee", "right_ankle"),
        ("left_shoulder", "left_elbow", "left_wrist"),
        ("right_shoulder", "right_elbow", "right_wrist"),
    ):
        u = poses[:, SKELETON.index(a)] - poses[:, SKELETON.index(b)]
        v = poses[:, SKELETON.index(c)] - poses[:, SKELETON.index(b)]
        out.append(angle_between_deg(u, v))
    return np.stack(out, 1)


def depth_side(truth_cam: np.ndarray, est_cam: np.ndarray, flags: np.ndarray | None) -> tuple[int, int, int]:
    """Limb segments over 30 degrees out of the image plane (by the truth) in frames whose child joint is not
    flagged: (right side, counted, flagged limb-frames)."""
    right = counted = flagged = 0
    for a, b in LIMB_BONES:
        ia, ib = SKELETON.index(a), SKELETON.index(b)
        seg_t, seg_e = truth_cam[:, ib] - truth_cam[:, ia], est_cam[:, ib] - est_cam[:, ia]
        ray = truth_cam[:, ib] / np.linalg.norm(truth_cam[:, ib], axis=-1, keepdims=True)
        along_t = (seg_t * ray).sum(-1) / np.linalg.norm(seg_t, axis=-1)
        along_e = (seg_e * ray).sum(-1)
        out_of_plane = np.abs(along_t) > np.sin(np.radians(30))
        ok = np.isfinite(along_e)
        f = np.zeros(len(ok), bool) if flags is None else flags[:, ib]
        flagged += int((f & ok).sum())
        use = out_of_plane & ok & ~f
        counted += int(use.sum())
        right += int((np.sign(along_e[use]) == np.sign(along_t[use])).sum())
    return right, counted, flagged


def too_fast_share(poses: np.ndarray) -> float:
    """% of the 12 joint angles' steps between consecutive lifted frames faster than 500 deg/s (zedo analyze's
    too-fast bound)."""
    angles = np.stack(list(joint_angles(poses, SKELETON).values()), 1)  # (T, 12)
    speed = np.abs(np.diff(angles, axis=0)) * FPS
    known = np.isfinite(speed)
    return 100 * float((speed[known] > 500).mean())


def angular_speed_p95(poses: np.ndarray) -> float:
    """The 95th percentile of the elbows' and knees' interior-angle speed (deg/s) between consecutive frames."""
    speed = np.abs(np.diff(interior_angles(poses), axis=0)) * FPS
    return float(np.nanpercentile(speed, 95))


def score(truth: np.ndarray, lifted: np.ndarray, reproj: np.ndarray) -> dict[str, float]:
    """Figures of one clip's lift against its camera-frame truth, over frames lifted."""
    ok = np.isfinite(lifted).all((1, 2))
    t_rel = truth - truth[:, SKELETON.root_indices].mean(1, keepdims=True)
    e_rel = lifted - lifted[:, SKELETON.root_indices].mean(1, keepdims=True)
    err = np.linalg.norm(e_rel[ok] - t_rel[ok], axis=-1)
    vel = np.diff(e_rel, axis=0) * FPS - np.diff(t_rel, axis=0) * FPS
    both = ok[1:] & ok[:-1]
    ang = np.abs(interior_angles(lifted[ok]) - interior_angles(truth[ok]))
    return {
        "cv": bone_cv(lifted[ok]),
        "mpjpe": 1000 * float(err.mean()),
        "angle": float(np.nanmean(ang)),
        "mpjve": 1000 * float(np.linalg.norm(vel[both], axis=-1).mean()),
        "reproj": float(np.nanmean(reproj[ok])),
        "fast": too_fast_share(lifted),
        "p95": angular_speed_p95(lifted),
        "p95_true": angular_speed_p95(truth),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--syrip-dir", required=True)
    ap.add_argument("--split", choices=("train", "test"), default="train")
    ap.add_argument("--clips", type=int, default=8)
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--camera", choices=("known", "pseudo"), default="known")
    ap.add_argument("--source", choices=("syrip", "adult"), default="syrip")
    ap.add_argument("--modes", nargs="+", default=list(MODES))
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--fit-ratio", action="store_true", help="print the skeleton shares' conformal quantile")
    ap.add_argument("--habits", action="store_true", help="adult source: add swaps, hand jumps and lost frames")
    ap.add_argument("--supine", action="store_true", help="syrip source: each pose turned chest to the camera first")
    ap.add_argument("--save-ratios", type=Path, help="save |log(estimated / true share)| of every bone (.npy)")
    args = ap.parse_args()
    prior = load_prior(resolve_prior_path(None))
    cfg = get_preset("fast")
    rng = np.random.default_rng(args.seed)
    data = clips_of(args, rng)
    rows: dict[str, list[dict[str, float]]] = {m: [] for m in args.modes}
    extra = {"side": [0, 0, 0], "ratio": [], "log_ratio": [], "cover": [], "limb_frames": 0}
    seconds = dict.fromkeys(args.modes, 0.0)
    for clip in range(args.clips):
        idx = np.flatnonzero(data["tracks"] == clip)
        truth = data["cam"][idx]
        for mode in args.modes:
            start = time.perf_counter()
            res = lift_sequence(data["xy"][idx], data["conf"][idx], data["k"][idx], prior, cfg, mode=mode, fps=FPS,
                                seed=args.seed)  # fmt: skip
            seconds[mode] += time.perf_counter() - start
            rows[mode].append(score(truth, res.poses_camera, res.reprojection_error_px))
            if mode == "clip":
                clip_figures(extra, truth, res)
                if "swapped" in data:
                    habit_figures(extra, data, idx, res)
    turned = ", turned supine" if args.supine else ""
    print(
        f"source {args.source} ({args.split}{turned}), camera {args.camera}, {args.clips} clips of {args.seconds:g} s"
    )
    print(
        "| mode | bone-length CV % | MPJPE mm | elbow/knee MAE deg | MPJVE mm/s | reprojection px | angle steps > 500 "
        "deg/s % | elbow/knee speed p95, lifted / true deg/s | s/clip |"
    )
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for mode in args.modes:
        m = {k: np.mean([r[k] for r in rows[mode]]) for k in rows[mode][0]}
        print(f"| {mode} | {m['cv']:.2f} | {m['mpjpe']:.1f} | {m['angle']:.1f} | {m['mpjve']:.0f} | {m['reproj']:.2f} "
              f"| {m['fast']:.2f} | {m['p95']:.0f} / {m['p95_true']:.0f} ({m['p95'] / m['p95_true'] - 1:+.0%}) "
              f"| {seconds[mode] / args.clips:.1f} |")  # fmt: skip
    if "clip" in args.modes:
        right, counted, flagged = extra["side"]
        print(
            f"clip: depth side right {100 * right / max(counted, 1):.1f} % of {counted} unflagged segment-frames "
            f"over 30 deg out of plane; flagged {100 * flagged / max(extra['limb_frames'], 1):.1f} % of limb-frames"
        )
        ratio = np.array(extra["ratio"])
        print(f"clip: bone shares within 5 % of the truth: {100 * np.mean(ratio < 0.05):.0f} % of bones "
              f"(median error {100 * np.median(ratio):.1f} %); 90 % intervals hold the true share "
              f"{100 * np.mean(extra['cover']):.0f} % ({len(extra['cover'])} bones)")  # fmt: skip
        if args.habits and "habits" in extra:
            h = extra["habits"]
            print(
                f"clip: swapped frames found {h[0]} of {h[1]} ({100 * h[0] / max(h[1], 1):.0f} %), false "
                f"{100 * h[2] / max(h[3], 1):.2f} % of the others; hand-jump joint-frames found {h[4]} of {h[5]} "
                f"({100 * h[4] / max(h[5], 1):.0f} %), false {100 * h[6] / max(h[7], 1):.2f} % of the others"
            )
        if args.save_ratios:
            np.save(args.save_ratios, np.array(extra["log_ratio"]))
        if args.fit_ratio:
            q = conformal_quantile(np.array(extra["log_ratio"]), 0.9)
            print(f"clip: the 90 % conformal quantile of |log(estimated / true share)| here: {q:.4f}")


def habit_figures(extra: dict, data: dict, idx: np.ndarray, res) -> None:  # noqa: ANN001
    """Injected swaps and hand jumps against what clip mode found (frames, joint-frames)."""
    found = extra.setdefault("habits", np.zeros(8, int))
    swapped, jump = data["swapped"][idx], data["hand_jump"][idx]
    found += [int((swapped & res.detection_swapped).sum()), int(swapped.sum()),
              int((~swapped & res.detection_swapped).sum()), int((~swapped).sum()),
              int((jump & res.detection_outliers).sum()), int(jump.sum()),
              int((~jump & res.detection_outliers).sum()), int((~jump).sum())]  # fmt: skip


def clip_figures(extra: dict, truth: np.ndarray, res) -> None:  # noqa: ANN001
    right, counted, flagged = depth_side(truth, res.poses_camera, res.depth_ambiguous)
    extra["side"] = [extra["side"][0] + right, extra["side"][1] + counted, extra["side"][2] + flagged]
    extra["limb_frames"] += int(np.isfinite(res.poses_camera).all((1, 2)).sum()) * len(LIMB_BONES)
    skel = res.track_skeletons[0]
    if "bones" not in skel:
        return
    true_len = {BONE_NAMES[(a, b)]: float(np.median(np.linalg.norm(truth[:, SKELETON.index(a)]
                                                                   - truth[:, SKELETON.index(b)], axis=-1)))
                for a, b in LIMB_BONES}  # fmt: skip
    total_t = sum(true_len.values())
    for b, bone in skel["bones"].items():
        share = true_len[b] / total_t
        extra["ratio"].append(abs(bone["share"] / share - 1))
        extra["log_ratio"].append(abs(np.log(bone["share"] / share)))
        extra["cover"].append(bone["share_low"] <= share <= bone["share_high"])


def adult_clips(args: argparse.Namespace) -> dict[str, np.ndarray]:
    """The adult motion made infant-like (`zedo_cli.evaluation.clips`), as `make_sequences` gives clips: 3 px
    jitter and 3 % of joints dropped, no other habit, before a camera of f = 1000 px or the pseudo camera."""
    from zedo_cli.evaluation.clips import (
        PSEUDO_CAMERA,
        CameraSetup,
        ClipSettings,
        DetectorHabits,
        adult_infant_clips,
        infant_bodies_from_syrip,
        load_adult_library,
    )

    camera = PSEUDO_CAMERA if args.camera == "pseudo" else CameraSetup("f1000", 1000.0, 1280, 720, (0.9, 1.1))
    habits = DetectorHabits(jitter_px=3.0, dropout=0.03, swaps_per_min=0, hand_jumps_per_min=0, losses_per_min=0)
    if args.habits:  # left/right swaps, a wrist on an adult's hand, lost frames, at the source's default rates
        habits = DetectorHabits(jitter_px=3.0, dropout=0.03)
    settings = ClipSettings(fps=FPS, cameras=(camera,), habits=habits)
    library = load_adult_library(Path(args.syrip_dir).parent / "adult")
    clips = list(adult_infant_clips(library, infant_bodies_from_syrip(args.syrip_dir), args.seconds, args.clips,
                                    args.seed, settings))  # fmt: skip
    k = [np.repeat(c.intrinsics.matrix()[None], len(c.xy), 0) for c in clips]
    masks = {"swapped": np.concatenate([c.masks.swapped for c in clips]),
             "hand_jump": np.concatenate([c.masks.hand_jump for c in clips])}  # fmt: skip
    return {**masks, "cam": np.concatenate([c.poses3d for c in clips]), "xy": np.concatenate([c.xy for c in clips]),
            "conf": np.concatenate([c.confidence for c in clips]), "k": np.concatenate(k),
            "tracks": np.concatenate([np.full(len(c.xy), i) for i, c in enumerate(clips)])}  # fmt: skip


def clips_of(args: argparse.Namespace, rng: np.random.Generator) -> dict[str, np.ndarray]:
    if args.source == "adult":
        return adult_clips(args)
    poses = load_syrip_3d(args.syrip_dir, args.split).poses
    if args.supine:
        poses = turned_supine(poses, SKELETON.joints)
    keys = int(args.seconds) + 1
    place = known_camera(1000.0) if args.camera == "known" else None
    return make_sequences(poses, rng, count=args.clips, keyposes=keys, transition_s=1.0, fps=FPS, noise_px=3.0,
                          drop=0.03, gap=3, place=place, interpolation="segments",
                          sway=Sway() if args.supine else None)  # fmt: skip


if __name__ == "__main__":
    main()
