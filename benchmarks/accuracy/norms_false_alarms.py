"""How often the comparison with typical infants calls a typical clip atypical, measured on many reference draws,
and how often it catches clips that are atypical by construction.

Sources (`--source`): the adult motion made infant-like (`zedo_cli.evaluation.clips`, poses the bundled prior never
saw: it was trained on SyRIP), the clinic cameras and the pseudo camera; SyRIP's training or Test100 poses, or its
synthetic poses (`benchmarks/lib/pose_sources.py`: outside every fit, for an independent check only), eased 1 s
apart before the pseudo camera, each in its own photo's orientation, the body turning and drifting at constant rates,
or, with `-supine`, turned chest to the camera and swaying about one place as the adult motion's clips do.
30 fps, 3 px jitter, 3 % dropped joints, each clip its own infant. Lifted as a user lifts a clip, without stating
the camera (`--temporal smooth`), and analysed with the defaults; the clip features are what `zedo norms` collects
(`compare.features_by_person`). Groups:
- `typical`: 10 s clips (the pool the references are drawn from and the typical clips tested);
- `long`: typical clips 6 times as long (60 s), compared with 10 s references (the feature z and the extended and
  asymmetry p by their six epochs of 10 s, as `zedo analyze --norms` compares them; the published p on the whole
  clip);
- `still_arm`: the left elbow and wrist held at their first frame's place in the trunk's frame (the kind the
  comparison was tuned on); `still_leg`: the left knee and ankle held so (a kind never used in tuning);
- `still_body` (only when asked for with `--groups`): every joint but the shoulders and hips held so, the lift's
  floor for the movement features: how much it moves limbs that do not move;
- `retest`: the first typical clips again, lifted with another seed and 1 px more jitter: each feature's
  test-retest agreement (ICC(2,1), absolute agreement).

`lift` makes and lifts the clips (one JSON line a clip under `--work`, resumed where it stopped; `--clips N`
extends a group to N clips); `true-speeds` prints the eased groups' true elbow speeds; `score` draws `--draws`
references of `--reference` typical clips and compares every other clip of `--groups` with each, printing per group
how many get p < 0.05 in the published, extended and calibrated comparisons, with a 95 % interval, and for the
groups compared by epochs how much their epochs agree.

    .venv/bin/python benchmarks/accuracy/norms_false_alarms.py lift --syrip-dir ../shared/data/syrip --work /tmp/nfa
    .venv/bin/python benchmarks/accuracy/norms_false_alarms.py score --work /tmp/nfa
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the repository root
from benchmarks.lib.pose_sources import EASED_SOURCES, SUPINE, SUPINE_SOURCES, eased_source_poses, source_sway
from benchmarks.lib.resumable_runs import append_row, read_rows
from zedo_cli.analysis.clip.published_features import PREREGISTERED
from zedo_cli.analysis.norms.calibrated import RELIABILITY_FILE, RELIABLE_ICC, ReliabilityEntry
from zedo_cli.analysis.norms.norms import (
    ClipValues,
    build_norms,
    compare,
    extended_names,
    infant_features,
    with_asymmetry,
)
from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.evaluation.clips import (
    ClipSettings,
    DetectorHabits,
    adult_infant_clips,
    infant_bodies_from_syrip,
    load_adult_library,
)
from zedo_cli.evaluation.clips.cameras import project_points
from zedo_cli.evaluation.clips.eased import IMAGE_H, IMAGE_W, make_sequences
from zedo_cli.evaluation.clips.stillness import hold_still
from zedo_cli.lifting.camera import Intrinsics
from zedo_cli.stats import icc_agreement

FPS = 30.0
JITTER_PX = 3.0
GROUPS = {  # name: (seconds, count, held joints, seed offset)
    "typical": (10.0, 260, (), 0),
    "long": (60.0, 40, (), 1000),
    "still_arm": (10.0, 30, ("left_elbow", "left_wrist"), 2000),
    "still_leg": (10.0, 30, ("left_knee", "left_ankle"), 3000),
    "still_body": (
        10.0,
        15,
        (
            "left_elbow",
            "right_elbow",
            "left_wrist",
            "right_wrist",
            "left_knee",
            "right_knee",
            "left_ankle",
            "right_ankle",
        ),
        4000,
    ),
}
DEFAULT_GROUPS = ("typical", "long", "still_arm", "still_leg")  # the documented figures' groups
RETEST = 80  # typical clips lifted a second time
SOURCES = ("adult", *EASED_SOURCES, *SUPINE_SOURCES)
JOINTS = get_skeleton("syrip12").joints
SOURCE_WORDS = {"adult": "adult motion made infant-like, clinic and pseudo cameras",
                "syrip-train": "SyRIP training poses eased 1 s apart, pseudo camera",
                "syrip-test": "SyRIP Test100 poses eased 1 s apart, pseudo camera",
                "syrip-synthetic": "SyRIP's synthetic poses (HW-HuP) eased 1 s apart, pseudo camera",
                **{s + SUPINE: f"{s}'s poses turned chest to the camera, eased 1 s apart, swaying, pseudo camera"
                   for s in EASED_SOURCES}}  # fmt: skip
KINDS = ("published", "extended", "asymmetry")
CALIBRATED_KINDS = KINDS[1:]
GROUP_WORDS = {"typical": "typical 10 s", "long": "typical 60 s", "still_arm": "still left arm",
               "still_leg": "still left leg"}  # fmt: skip


def habits(jitter_px: float) -> DetectorHabits:
    return DetectorHabits(jitter_px=jitter_px, dropout=0.03, swaps_per_min=0, hand_jumps_per_min=0, losses_per_min=0)


Clip2D = tuple[np.ndarray, np.ndarray, tuple[int, int], str]  # 2D (T, 12, 2), confidence (T, 12), image size, camera


def clip_count(args: argparse.Namespace, group: str) -> int:
    """How many clips of `group` to make: `--clips`, else the group's own count. The first clips of a larger count
    are the clips of a smaller one, so a lifted group is extended, not redrawn."""
    return getattr(args, "clips", None) or GROUPS[group][1]


def adult_clips(args: argparse.Namespace, group: str) -> Iterator[Clip2D]:
    """The group's clips of the adult motion made infant-like (`zedo_cli.evaluation.clips`), in order."""
    seconds, _, held, offset = GROUPS[group]
    count = clip_count(args, group)
    library = load_adult_library(Path(args.syrip_dir).parent / "adult")
    settings = ClipSettings(fps=FPS, habits=habits(args.jitter_px))
    made = adult_infant_clips(library, infant_bodies_from_syrip(args.syrip_dir), seconds, count, args.seed + offset,
                              settings)  # fmt: skip
    for i, clip in enumerate(made):
        xy = clip.xy
        if held:
            rng = np.random.default_rng([args.seed, offset, i])
            poses = hold_still(clip.poses3d, JOINTS, held)
            xy = project_points(poses, clip.intrinsics) + rng.normal(0.0, args.jitter_px, clip.xy.shape)
            xy[~np.isfinite(clip.xy).all(-1)] = np.nan  # the clip's dropped joints
        yield xy, clip.confidence, clip.image_size, clip.camera


def eased_clips(args: argparse.Namespace, group: str, truth: list[np.ndarray] | None = None) -> Iterator[Clip2D]:
    """The group's clips of SyRIP poses eased one into the next 1 s apart (`zedo_cli.evaluation.clips.eased`: the
    body turning and drifting about 1 m before the pseudo camera), in order; `truth` gets each clip's true
    root-relative poses (T, 12, 3)."""
    seconds, _, held, offset = GROUPS[group]
    count = clip_count(args, group)
    poses = eased_source_poses(args.syrip_dir, args.source)
    intrinsics = Intrinsics.pseudo(IMAGE_W, IMAGE_H)
    for i in range(count):
        rng = np.random.default_rng([args.seed, offset, i])
        seq = make_sequences(poses, rng, count=1, keyposes=int(seconds) + 1, transition_s=1.0, fps=FPS,
                             noise_px=args.jitter_px, drop=0.03, gap=0, turn_scale=args.turn_scale,
                             sway=source_sway(args.source))  # fmt: skip
        xy, conf, rel = seq["xy"], seq["conf"], seq["rel"]
        if held:
            rel = hold_still(seq["rel"], JOINTS, held)
            xy = project_points(rel + (seq["cam"] - seq["rel"]), intrinsics) + rng.normal(0.0, args.jitter_px, xy.shape)
            xy[conf == 0] = np.nan
        if truth is not None:
            truth.append(rel)
        yield xy, conf, (IMAGE_W, IMAGE_H), "pseudo"


def true_speeds(args: argparse.Namespace) -> int:
    """Per group of eased clips, the median over its clips of each elbow's true 3D median angular speed (the
    `3d_` feature of the true poses): what the lifted speeds that `experiments/norms_scores.py` prints compare with."""
    from zedo_cli.analysis.clip.features_3d import features_3d

    for group in args.groups:
        truth: list[np.ndarray] = []
        for _ in eased_clips(args, group, truth):
            pass
        values = [features_3d(rel, get_skeleton("syrip12"), FPS).values for rel in truth]
        left, right = (np.nanmedian([v.get(f"3d_median_vel_angle_{s}Elbow", np.nan) for v in values]) for s in "LR")
        print(f"{group} ({len(truth)} clips), true elbows' median speed: left {left:.1f} / right {right:.1f} deg/s")
    return 0


def write_2d(path: Path, xy: np.ndarray, confidence: np.ndarray, image_size: tuple[int, int]) -> None:
    """zedo JSON Lines 2D (syrip12 joints), one person per frame, the image size on the first line."""
    with path.open("w") as f:
        for i, (p, c) in enumerate(zip(xy, confidence, strict=True)):
            points = [None if not (w > 0 and np.isfinite(x).all()) else [float(x[0]), float(x[1]), float(w)]
                      for x, w in zip(p, c, strict=True)]  # fmt: skip
            record: dict = {"frame": i, "persons": [{"keypoints": points}]}
            if i == 0:
                record["image_size"] = list(image_size)
            f.write(json.dumps(record) + "\n")


def lift_features(path: Path, seed: int, epoch_s: float | None = None, temporal: str = "smooth"
                  ) -> tuple[dict[str, float], float | None, list[dict[str, float]]]:  # fmt: skip
    """The clip's features as `zedo norms` keeps them, its length, and (with `epoch_s`) its epochs' features as
    `zedo analyze --norms` takes them from a clip longer than the reference's (`compare.epoch_values`)."""
    import zedo_cli
    from zedo_cli.analysis.compare import epoch_values, features_by_person

    lifted = zedo_cli.lift_file(str(path), skeleton="syrip12", fps=FPS, temporal=temporal, seed=seed)
    a = zedo_cli.analyze(lifted)
    clip = features_by_person(a)[0]
    return clip.values, clip.seconds, epoch_values(a, clip.person, epoch_s) if epoch_s else []


def finite_or_none(values: dict[str, float]) -> dict[str, float | None]:
    return {k: (v if math.isfinite(v) else None) for k, v in values.items()}


def lift(args: argparse.Namespace) -> int:
    folder = args.work / args.source
    folder.mkdir(parents=True, exist_ok=True)
    make = adult_clips if args.source == "adult" else eased_clips
    t0 = time.perf_counter()
    for group in args.groups:
        out = folder / f"{group}.jsonl"
        epoch_s = GROUPS["typical"][0] if group == "long" else None  # the references' clips' length
        done = {r["clip"] for r in read_rows(out) if epoch_s is None or "epochs" in r}
        count = clip_count(args, group)
        for i, (xy, confidence, size, camera) in enumerate(make(args, group)):
            retest = group == "typical" and i < RETEST and f"{i}r" not in done
            if i in done and not retest:
                continue
            runs = [] if i in done else [(i, xy, 0)]
            if retest:  # another seed and 1 px more jitter
                runs.append((f"{i}r", xy + np.random.default_rng([args.seed, 9, i]).normal(0.0, 1.0, xy.shape), 1))
            for name, points, seed in runs:
                path = folder / f"{group}.2d.jsonl"
                write_2d(path, points, confidence, size)
                values, length, epochs = lift_features(path, seed, epoch_s, args.temporal)
                row = {"clip": name, "camera": camera, "seconds": length, "values": finite_or_none(values)}
                if epoch_s is not None:
                    row["epochs"] = [finite_or_none(e) for e in epochs]
                append_row(out, row)
            print(f"{args.source} {group} {i + 1}/{count} ({time.perf_counter() - t0:.0f} s)", flush=True)
    return 0


def lift_parser(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    """The `lift` sub-command's parser: where the data are, where the clips go, which source and seed."""
    p = sub.add_parser("lift")
    p.add_argument("--syrip-dir", required=True)
    p.add_argument("--work", type=Path, required=True)
    p.add_argument("--source", choices=SOURCES, default="adult")
    p.add_argument("--seed", type=int, default=0)
    return p


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="command", required=True)
    p = lift_parser(sub)
    p.add_argument("--groups", nargs="+", choices=list(GROUPS), default=list(DEFAULT_GROUPS))
    p.add_argument("--temporal", choices=("smooth", "clip"), default="smooth",
                   help="how the clips are lifted (the documented figures: smooth)")  # fmt: skip
    p.add_argument("--jitter-px", type=float, default=JITTER_PX, help="the detector's jitter (px)")
    p.add_argument("--turn-scale", type=float, default=1.0, help="eased clips: scales the body's turning (0: none)")
    p.add_argument("--clips", type=int, default=None,
                   help="clips per group (default: each group's own count); more extends a lifted group")  # fmt: skip
    t = sub.add_parser("true-speeds")
    t.add_argument("--syrip-dir", required=True)
    t.add_argument("--source", choices=[s for s in SOURCES if s != "adult"], default="syrip-train")
    t.add_argument("--seed", type=int, default=0)
    t.add_argument("--groups", nargs="+", choices=list(GROUPS), default=list(GROUPS))
    t.add_argument("--turn-scale", type=float, default=1.0)
    t.set_defaults(jitter_px=JITTER_PX)
    r = sub.add_parser("reliability")
    r.add_argument("--work", type=Path, required=True)
    r.add_argument("--sources", nargs="+", choices=SOURCES, default=["adult", "syrip-train"])
    r.add_argument("--out", type=Path, help="write the reliability file here (zedo_cli/weights/reliability.json)")
    s = sub.add_parser("score")
    s.add_argument("--work", type=Path, required=True)
    s.add_argument("--sources", nargs="+", choices=SOURCES, default=["adult", *EASED_SOURCES])
    s.add_argument("--reference", type=int, default=20)
    s.add_argument("--draws", type=int, default=10)
    s.add_argument("--seed", type=int, default=0)
    s.add_argument("--groups", nargs="+", choices=list(GROUP_WORDS), default=list(GROUP_WORDS),
                   help="the groups of clips compared with each reference (default all)")  # fmt: skip
    args = ap.parse_args()
    commands = {"lift": lift, "true-speeds": true_speeds, "reliability": reliability, "score": score}
    return commands[args.command](args)


def _known(values: dict[str, float | None]) -> dict[str, float]:
    return {k: math.nan if v is None else v for k, v in values.items()}


def clip_rows(folder: Path, group: str) -> dict[str | int, dict[str, float]]:
    """The group's clips by name (an int; `<i>r` for a retest), their features as `zedo norms` keeps them (a clip
    lifted again: its last row)."""
    rows = read_rows(folder / f"{group}.jsonl")
    return {r["clip"]: with_asymmetry(infant_features(_known(r["values"]))) for r in rows}


def clip_epochs(folder: Path, group: str) -> dict[str | int, list[dict[str, float]]]:
    """The group's clips' epochs as `zedo analyze --norms` compares a clip longer than the reference's (none where a
    row has none)."""
    return {r["clip"]: [_known(e) for e in r.get("epochs", [])] for r in read_rows(folder / f"{group}.jsonl")}


Values = dict[str, float]


def retest_pairs(clips: dict[str | int, Values]) -> list[tuple[Values, Values]]:
    """Each typical clip's features with its retest's (`<i>` and `<i>r`), for the clips that have one."""
    return [(v, clips[f"{i}r"]) for i, v in clips.items() if isinstance(i, int) and f"{i}r" in clips]


def retest_icc(pairs: list[tuple[Values, Values]], names: list[str]) -> dict[str, float]:
    """Each feature's ICC(2,1) (absolute agreement) between the clips and their retests."""
    return {n: icc_agreement(np.array([[a.get(n, math.nan), b.get(n, math.nan)] for a, b in pairs])) for n in names}


def reliability(args: argparse.Namespace) -> int:
    """Each feature's ICC(2,1) between the typical clips and their retests, per source; written as the shipped
    reliability file."""
    entries = []
    for source in args.sources:
        clips = clip_rows(args.work / source, "typical")
        pairs = retest_pairs(clips)
        icc = retest_icc(pairs, sorted(set(PREREGISTERED) | set().union(*(extended_names(a) for a, _ in pairs))))
        kept = sum(v >= RELIABLE_ICC for v in icc.values())
        print(f"{source}: {len(pairs)} clips and retests; {kept} of {len(icc)} features with ICC >= {RELIABLE_ICC}")
        for name in sorted(icc, key=icc.get)[:12]:
            print(f"  {icc[name]:6.3f} {name}")
        command = ("python benchmarks/accuracy/norms_false_alarms.py reliability --work <work> --sources "
                   + " ".join(args.sources))  # fmt: skip
        entries.append(ReliabilityEntry(
            source=SOURCE_WORDS[source], clips=len(pairs), temporal_mode="smooth",
            icc={n: round(v, 4) for n, v in icc.items() if math.isfinite(v)},
            provenance={"command": command, "retest": "the same 2D lifted with another seed and 1 px more jitter",
                        "data": "adult motion capture (../shared/data/adult) retargeted to SyRIP training infants; "
                                "SyRIP training poses (../shared/data/syrip, non-commercial terms)"}))  # fmt: skip
    if args.out:
        RELIABILITY_FILE.write(args.out, entries)
        print(f"wrote {args.out}")
    return 0


def rate_interval(per_draw: list[list[bool]], rng: np.random.Generator) -> tuple[float, float, float, int]:
    """The share of (clip, draw) cases flagged and its 95 % interval, resampling the reference draws (a draw's cases
    together: a reference drawn with an outlier among it flags fewer clips, so draws, not cases, are the unit)."""
    flagged = np.array([sum(d) for d in per_draw], float)
    counts = np.array([len(d) for d in per_draw], float)
    boot = rng.integers(len(per_draw), size=(2000, len(per_draw)))
    shares = flagged[boot].sum(1) / counts[boot].sum(1)
    return float(flagged.sum() / counts.sum()), *np.percentile(shares, [2.5, 97.5]), int(counts.sum())


def score(args: argparse.Namespace) -> int:
    """Per source, draw references of the typical clips and compare every other clip with each."""
    print("| source | clips | cases | published | extended | asymmetry, calibrated |")
    print("| --- | --- | --- | --- | --- | --- |")
    for source in args.sources:
        folder = args.work / source
        typical = {i: v for i, v in clip_rows(folder, "typical").items() if isinstance(i, int)}
        others = {
            g: clip_rows(folder, g) for g in ("long", "still_arm", "still_leg") if (folder / f"{g}.jsonl").exists()
        }
        epochs = {g: clip_epochs(folder, g) for g in others}
        rng = np.random.default_rng(args.seed)
        hits: dict[str, dict[str, list[list[bool]]]] = {}
        agreement: dict[str, dict[str, list[tuple[float, int]]]] = {}  # per epoch-compared group and calibrated p
        for _ in range(args.draws):
            drawn = rng.permutation(sorted(typical))
            reference = build_norms([ClipValues(str(i), 0, typical[i]) for i in drawn[: args.reference]], "benchmark")
            tested = {"typical": {i: typical[i] for i in drawn[args.reference :]}, **others}
            tested = {g: clips for g, clips in tested.items() if g in args.groups}
            for group, clips in tested.items():
                if not clips:
                    continue
                found = [compare(values, reference, None, epochs=epochs.get(group, {}).get(name) or None)
                         for name, values in clips.items()]  # fmt: skip
                for kind in KINDS:
                    hits.setdefault(group, {}).setdefault(kind, []).append([getattr(c, kind).p < 0.05 for c in found])
                for kind in CALIBRATED_KINDS if epochs.get(group) else ():
                    agreement.setdefault(group, {}).setdefault(kind, []).extend(
                        (getattr(c, kind).epoch_agreement, getattr(c, kind).independent_epochs) for c in found
                    )
        for group, kinds in hits.items():
            cells = []
            for kind in KINDS:
                rate, low, high, cases = rate_interval(kinds[kind], rng)
                cells.append(f"{rate:.1%} ({low:.1%}-{high:.1%})")
            clips = len(typical) if group == "typical" else len(others[group])
            print(f"| {source} | {GROUP_WORDS[group]}: {clips} | {cases} | " + " | ".join(cells) + " |")
        for group, kinds in agreement.items():
            print(f"  {source}, {GROUP_WORDS[group]} by epochs: " + "; ".join(
                f"{kind} p, median epoch agreement {np.median([a for a, _ in v]):.2f}, independent epochs "
                f"{np.median([n for _, n in v]):g} (of {len(v)} cases)" for kind, v in kinds.items()))  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
