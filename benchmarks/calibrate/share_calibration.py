"""The clip share of frames asymmetric (`<pair>_share_asymmetric`) against the truth, per clip source and length;
the share's calibration across sources, checked leaving one source out; writes `zedo_cli/weights/share.json`.

The share's bootstrap interval (`analysis.uncertainty.clip_share`) says how far the frames' own calibrated
uncertainty lets the share move; it narrows with the clip's length. Where the frames' calibration is biased on a
source (another pose set, another motion), the bias survives any length: the calibration here bounds the share's
error as measured on whole clips of other sources, a split-conformal quantile of |estimate - truth| per pair,
which does not shrink with length.

Sources (each clip one infant, 3 px jitter, 3 % dropped joints, 30 fps, lifted as a user lifts a clip: no camera
stated, `--temporal smooth`, then `zedo analyze` with its defaults):
- `adult`: the adult motion made infant-like (`zedo_cli.evaluation.clips`; poses the bundled prior never saw),
  the clinic cameras and the pseudo camera;
- `syrip-train`: SyRIP training poses eased 1 s apart before the pseudo camera (the bundled prior was trained on
  these poses: its lifts are in-sample, so this source's errors are the small side);
- `syrip-train-supine`: the same poses turned chest to the camera, the body swaying about one place (fitted on,
  left out together with `syrip-train`: the same poses);
- `syrip-test`, `syrip-synthetic` (and their `-supine` twins): Test100's and the synthetic poses: checked, never
  fitted on.
Lengths: 10 s, 60 s and 180 s.

    python benchmarks/calibrate/share_calibration.py lift --syrip-dir ../shared/data/syrip --work /tmp/share \
        --source adult
    python benchmarks/calibrate/share_calibration.py fit --work /tmp/share [--out zedo_cli/weights/share.json]
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the repository root
from benchmarks.accuracy.norms_false_alarms import FPS, JITTER_PX, SOURCE_WORDS, habits, lift_parser, write_2d
from benchmarks.lib.pose_sources import SUPINE, eased_source_poses, source_sway
from benchmarks.lib.resumable_runs import append_row, read_rows
from zedo_cli.analysis.analyse import SYMMETRY_NAMES, bootstrap_share
from zedo_cli.analysis.pose.symmetry import DEFAULT_THRESHOLD_DEG, symmetry_angles
from zedo_cli.analysis.uncertainty.calibration import LEVELS
from zedo_cli.analysis.uncertainty.share_calibration import SHARE_FILE, ShareMargin
from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.evaluation.clips import ClipSettings, adult_infant_clips, infant_bodies_from_syrip, load_adult_library
from zedo_cli.evaluation.clips.eased import IMAGE_H, IMAGE_W, make_sequences
from zedo_cli.stats import pearson, require_quantile

LENGTHS = {10.0: 60, 60.0: 16, 180.0: 6}  # seconds: clips
NEAR_DEG = 10.0  # a frame's estimate this close to the threshold counts as near it
LEVEL = 0.9  # the level of the tables (the file holds every level of LEVELS)
THRESHOLDS = (15.0, 28.0, 45.0)  # degrees: the calibrated symmetry thresholds (28: zedo analyze's default)
SKELETON = get_skeleton("syrip12")
Truth = tuple[np.ndarray, np.ndarray, np.ndarray, tuple[int, int]]  # 3D (T, 12, 3), 2D, confidence, image size


def adult_clips(args: argparse.Namespace, seconds: float, count: int) -> Iterator[Truth]:
    library = load_adult_library(Path(args.syrip_dir).parent / "adult")
    settings = ClipSettings(fps=FPS, habits=habits(JITTER_PX))
    for clip in adult_infant_clips(library, infant_bodies_from_syrip(args.syrip_dir), seconds, count,
                                   args.seed + int(seconds), settings):  # fmt: skip
        yield clip.poses3d, clip.xy, clip.confidence, clip.image_size


def eased_clips(args: argparse.Namespace, seconds: float, count: int) -> Iterator[Truth]:
    poses = eased_source_poses(args.syrip_dir, args.source)
    if int(seconds) + 1 > len(poses):
        print(f"{args.source}: {len(poses)} poses make no {seconds:g} s clip of distinct key poses 1 s apart")
        return
    for i in range(count):
        rng = np.random.default_rng([args.seed, int(seconds), i])
        seq = make_sequences(poses, rng, count=1, keyposes=int(seconds) + 1, transition_s=1.0, fps=FPS,
                             noise_px=JITTER_PX, drop=0.03, gap=0, sway=source_sway(args.source))  # fmt: skip
        yield seq["cam"], seq["xy"], seq["conf"], (IMAGE_W, IMAGE_H)


def share_cases(path: Path, truth3d: np.ndarray) -> list[dict]:
    """Lift and analyse the clip at `path` at each of THRESHOLDS; per threshold and symmetry pair the share's estimate
    and interval, and the true share over the same frames (those with a calibrated value)."""
    import zedo_cli

    lifted = zedo_cli.lift_file(str(path), skeleton="syrip12", fps=FPS, temporal="smooth")
    out = []
    for threshold in THRESHOLDS:
        a = zedo_cli.analyze(lifted, symmetry_threshold=threshold)
        truth = symmetry_angles(truth3d[a.result.frame_index[a.index]], SKELETON)
        frames, every = a.result.frame_index[a.index], np.ones(len(a.index), bool)
        for k, name in enumerate(SYMMETRY_NAMES):
            share = bootstrap_share(a, name, every, frames, seed=k)
            counted = np.isfinite(a.probabilities[name])
            if share is None:
                continue
            p = a.probabilities[name][counted]
            low, high = (end[counted] for end in a.intervals[name])
            near = np.abs(a.values[name][counted] - threshold) < NEAR_DEG
            out.append({"pair": name.removesuffix("_deg"), "threshold_deg": threshold, "estimate": share.value,
                        "low": share.low, "high": share.high, "truth": float(np.mean(truth[name][counted] > threshold)),
                        "frames": int(counted.sum()), "calibration": a.calibration_note,
                        "frame_width": float(np.median(high - low)), "uncertain": float(np.mean(4 * p * (1 - p))),
                        "near": float(near.mean())})  # fmt: skip
    return out


def lift(args: argparse.Namespace) -> int:
    folder = args.work / args.source
    folder.mkdir(parents=True, exist_ok=True)
    make = adult_clips if args.source == "adult" else eased_clips
    out = folder / "cases.jsonl"
    done = {(r["seconds"], r["clip"]) for r in read_rows(out)}
    t0 = time.perf_counter()
    for seconds, count in LENGTHS.items():
        for i, (truth3d, xy, conf, size) in enumerate(make(args, seconds, count)):
            if (seconds, i) in done:
                continue
            path = folder / "clip.2d.jsonl"
            write_2d(path, xy, conf, size)
            row = {"seconds": seconds, "clip": i, "pairs": share_cases(path, truth3d)}
            append_row(out, row)
            print(f"{args.source} {seconds:g} s {i + 1}/{count} ({time.perf_counter() - t0:.0f} s)", flush=True)
    return 0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="command", required=True)
    lift_parser(sub)
    f = sub.add_parser("fit")
    f.add_argument("--work", type=Path, required=True)
    f.add_argument("--out", type=Path)
    f.add_argument("--fitted", nargs="+", choices=list(SOURCE_WORDS), default=list(FITTED),
                   help="the sources the margins are fitted on (default: the shipped file's)")  # fmt: skip
    args = ap.parse_args()
    return {"lift": lift, "fit": fit}[args.command](args)


# The sources the shipped margins are fitted on (SyRIP's training poses in their photos' orientations and filmed
# supine: one pose set, left out together); syrip-test and the synthetic poses are only checked.
FITTED = ("adult", "syrip-train", "syrip-train-supine")


def load_cases(work: Path) -> list[dict]:
    """Every (source, clip, pair, threshold) case lifted under `work`, flat."""
    cases = []
    for source in SOURCE_WORDS:
        for row in read_rows(work / source / "cases.jsonl"):
            for pair in row["pairs"]:
                cases.append({"source": source, "seconds": row["seconds"], "clip": row["clip"], **pair})
    return [c for c in cases if c["truth"] is not None and np.isfinite(c["estimate"])]


def margins_from(cases: list[dict], level: float) -> dict[tuple[str, float], tuple[float, int]]:
    """(pair, threshold) -> (the split-conformal quantile of |estimate - truth| at `level`, cases)."""
    out = {}
    for key in sorted({(c["pair"], c["threshold_deg"]) for c in cases}):
        errors = np.array([abs(c["estimate"] - c["truth"]) for c in cases if (c["pair"], c["threshold_deg"]) == key])
        out[key] = (require_quantile(errors, level, f"{key[0]} at {key[1]:g} deg"), len(errors))
    return out


def same_poses(a: str, b: str) -> bool:
    """Whether two sources share their poses (`syrip-train` and `syrip-train-supine` do): left out together."""
    return a.removesuffix(SUPINE) == b.removesuffix(SUPINE)


def coverage_table(cases: list[dict], fitted: tuple[str, ...] = FITTED) -> None:
    """Per source and length: the bootstrap interval's coverage and width, and the widened interval's with margins
    fitted on the `fitted` sources that share no poses with it (leave one source out)."""
    print("| source | clip length | (clip, pair) cases | bootstrap alone: holds | median width | mean error "
          "| with margins from the other sources: holds | median width |")  # fmt: skip
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    default = [c for c in cases if c["threshold_deg"] == DEFAULT_THRESHOLD_DEG]
    for source in SOURCE_WORDS:
        margins = margins_from([c for c in cases if c["source"] in fitted and not same_poses(c["source"], source)],
                               LEVEL)  # fmt: skip
        for seconds in LENGTHS:
            mine = [c for c in default if c["source"] == source and c["seconds"] == seconds]
            if not mine:
                continue
            est, truth = np.array([c["estimate"] for c in mine]), np.array([c["truth"] for c in mine])
            low, high = np.array([c["low"] for c in mine]), np.array([c["high"] for c in mine])
            held = (low <= truth) & (truth <= high)
            start = (f"| {source} | {seconds:g} s | {len(mine)} | {held.mean():.1%} | {np.median(high - low):.2f} | "
                     f"{np.mean(est - truth):+.3f} |")  # fmt: skip
            if not all((c["pair"], c["threshold_deg"]) in margins for c in mine):
                print(f"{start} - | - |")  # no other fitted source
                continue
            q = np.array([margins[(c["pair"], c["threshold_deg"])][0] for c in mine])
            wide_low, wide_high = np.maximum(0, np.minimum(low, est - q)), np.minimum(1, np.maximum(high, est + q))
            wide_held = (wide_low <= truth) & (truth <= wide_high)
            print(f"{start} {wide_held.mean():.1%} | {np.median(wide_high - wide_low):.2f} |")


def difficulty_table(cases: list[dict]) -> None:
    """Pearson's r of the share's absolute error with each per-clip difficulty the analysis knows (the frames'
    median interval width, their mean 4 p (1 - p), the share of frames within NEAR_DEG of the threshold), per source
    and length: a margin scaled by one would need it to track the error (docs/decisions.md)."""
    print("\n| source | clip length | r with the frame width | r with 4 p (1 - p) | r with the share near the "
          "threshold |")  # fmt: skip
    print("| --- | --- | --- | --- | --- |")
    for source in SOURCE_WORDS:
        for seconds in LENGTHS:
            mine = [c for c in cases if c["source"] == source and c["seconds"] == seconds
                    and c["threshold_deg"] == DEFAULT_THRESHOLD_DEG and "near" in c]  # fmt: skip
            if len(mine) < 3:
                continue
            error = np.array([abs(c["estimate"] - c["truth"]) for c in mine])
            r = [pearson(error, np.array([c[k] for c in mine])) for k in ("frame_width", "uncertain", "near")]
            print(f"| {source} | {seconds:g} s | " + " | ".join(f"{x:+.2f}" for x in r) + " |")


def fit(args: argparse.Namespace) -> int:
    cases = load_cases(args.work)
    coverage_table(cases, tuple(args.fitted))
    difficulty_table(cases)
    fitted = [c for c in cases if c["source"] in args.fitted]
    sources = sorted({c["source"] for c in fitted})
    entries = []
    for level in LEVELS:
        for (pair, threshold), (margin, count) in margins_from(fitted, level).items():
            entries.append(ShareMargin(pair=pair, threshold_deg=threshold, level=level, margin=round(margin, 4),
                                       cases=count, sources=[SOURCE_WORDS[s] for s in sources], provenance={
                    "command": "python benchmarks/calibrate/share_calibration.py fit --work <work> --out <file>"
                               + ("" if tuple(args.fitted) == FITTED else f" --fitted {' '.join(args.fitted)}"),
                    "lengths": ", ".join(f"{s:g} s" for s in LENGTHS),
                    "data": "adult motion capture (../shared/data/adult) retargeted to SyRIP training infants; "
                            "SyRIP training poses (../shared/data/syrip, non-commercial terms)"}))  # fmt: skip
    if args.out:
        SHARE_FILE.write(args.out, entries)
        print(f"wrote {args.out}: {len(entries)} margins")
    for e in entries:
        if e.level == LEVEL:
            print(f"{e.pair} {e.threshold_deg:g} deg: margin {e.margin:.3f} over {e.cases} cases")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
