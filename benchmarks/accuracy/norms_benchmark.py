"""Does the comparison with typical infants flag what it should, and only that?

Synthetic 30 fps clips of one generator (zedo_cli/evaluation/clips/eased.py's: SyRIP key poses eased 1 s apart, the
body turning and drifting, 3 px noise, 3 % dropped joints), made from the held-out poses of a fold
(benchmarks/lib/folds.py) and lifted by that fold's prior, so that the prior never saw them:
- `--reference` clips (20) build the reference with `zedo norms`;
- `--typical` further clips (10) of the same generator: each should get p > 0.05, in every comparison;
- `--still` clips (5) whose left arm stays still relative to the trunk (the left elbow and wrist keep
  their first frame's place in the trunk's frame while the rest moves): each should get p < 0.05.

Every step runs through the command line, as a user would: `zedo lift --temporal smooth`, `zedo norms`,
`zedo analyze --norms --json`. Prints each clip's published z and p, its extended score and calibrated p, the
calibrated asymmetry p, and the counts.

    python benchmarks/accuracy/norms_benchmark.py --syrip-dir ../shared/data/syrip --folds folds/ --work /tmp/norms

Test100 and SyRIP's synthetic rows are never read.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the repository root
from benchmarks.lib.folds import held_out_names
from zedo_cli.data.datasets import load_syrip_3d
from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.evaluation.clips.eased import IMAGE_H, IMAGE_W, make_sequences
from zedo_cli.evaluation.clips.stillness import hold_still

FPS = 30.0
LEFT_ARM = ("left_elbow", "left_wrist")


def write_clip(path: Path, xy: np.ndarray, conf: np.ndarray) -> None:
    """zedo JSON Lines 2D (syrip12 joints), one person per frame, the image size on the first line."""
    with path.open("w") as f:
        for i, (p, c) in enumerate(zip(xy, conf, strict=True)):
            points = [None if w == 0 else [round(float(x), 2), round(float(y), 2), float(w)]
                      for (x, y), w in zip(p, c, strict=True)]  # fmt: skip
            record: dict = {"frame": i, "persons": [{"keypoints": points}]}
            if i == 0:
                record["image_size"] = [IMAGE_W, IMAGE_H]
            f.write(json.dumps(record) + "\n")


def make_clips(poses: np.ndarray, joints: tuple[str, ...], rng: np.random.Generator, count: int, seconds: float,
               still: bool) -> list[tuple[np.ndarray, np.ndarray]]:  # fmt: skip
    """`count` clips of `seconds` as (2D, confidence); with `still`, the left arm is held still in the trunk."""
    from zedo_cli.lifting.camera import Intrinsics

    clips = []
    for _ in range(count):
        seq = make_sequences(poses, rng, count=1, keyposes=int(seconds) + 1, transition_s=1.0, fps=FPS,
                             noise_px=3.0, drop=0.03, gap=0)  # fmt: skip
        xy, conf = seq["xy"], seq["conf"]
        if still:
            rel = hold_still(seq["rel"], joints, LEFT_ARM)
            cam = rel + (seq["cam"] - seq["rel"])  # the same root path
            k = Intrinsics.pseudo(IMAGE_W, IMAGE_H).matrix()
            uvw = cam @ k.T
            xy = uvw[..., :2] / uvw[..., 2:] + rng.normal(0.0, 3.0, cam.shape[:2] + (2,))
            xy[conf == 0] = np.nan
        clips.append((xy, conf))
    return clips


def zedo(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "zedo_cli", *args], check=True, capture_output=True, text=True)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--syrip-dir", required=True)
    ap.add_argument("--folds", type=Path, required=True)
    ap.add_argument("--fold", type=int, default=0)
    ap.add_argument("--work", type=Path, required=True, help="a folder for the clips, results and reference")
    ap.add_argument("--reference", type=int, default=20)
    ap.add_argument("--typical", type=int, default=10)
    ap.add_argument("--still", type=int, default=5)
    ap.add_argument("--seconds", type=float, default=20.0)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--reuse", action="store_true", help="compare the results already in --work (no new lifts)")
    args = ap.parse_args()
    prior = args.folds / f"fold{args.fold}.safetensors"
    if not prior.exists():
        raise SystemExit(f"{prior}: no fold prior (train it: docs/clinical.md)")
    names = set(held_out_names(args.folds, args.fold))
    train = load_syrip_3d(args.syrip_dir, "train")
    poses = train.poses[[i for i, n in enumerate(train.names) if n in names]]
    joints = get_skeleton("syrip12").joints
    rng = np.random.default_rng(args.seed)
    groups = {"reference": (args.reference, False), "typical": (args.typical, False), "still": (args.still, True)}
    t0 = time.perf_counter()
    for group, (count, still) in groups.items() if not args.reuse else ():
        folder = args.work / group
        folder.mkdir(parents=True, exist_ok=True)
        inputs = []
        for i, (xy, conf) in enumerate(make_clips(poses, joints, rng, count, args.seconds, still)):
            write_clip(folder / f"{group}{i:02d}.jsonl", xy, conf)
            inputs.append(str(folder / f"{group}{i:02d}.jsonl"))
        zedo("lift", *inputs, "--skeleton", "syrip12", "--fps", str(FPS), "--temporal", "smooth", "--prior",
             str(prior), "--output-dir", str(folder), "--overwrite", "-q")  # fmt: skip
    lifted = time.perf_counter() - t0
    norms = args.work / "norms.json"
    zedo("norms", str(args.work / "reference"), "-o", str(norms), "--overwrite", "-q")
    counts = {}
    print(f"{'clip':<12} {'published z':>12} {'p':>7} {'extended score':>15} {'p':>7} {'asymmetry p':>12}")
    for group in ("typical", "still"):
        flagged = {"published": 0, "extended": 0, "asymmetry": 0}
        results = sorted((args.work / group).glob("*.zedo.json"))
        for path in results:
            doc = json.loads(zedo("analyze", str(path), "--norms", str(norms), "--json", "-q").stdout)
            v = {r["measure"]: r["value"] for r in doc["rows"] if r["measure"].startswith("surprise_")}
            for kind in flagged:
                p = v[f"surprise_{kind}_p"]
                flagged[kind] += int(p is not None and p < 0.05)
            print(f"{path.name.split('.')[0]:<12} {v['surprise_published_z']:>12.2f} {v['surprise_published_p']:>7.3f} "
                  f"{v['surprise_extended_score']:>15.2f} {v['surprise_extended_p']:>7.3f} "
                  f"{v['surprise_asymmetry_p']:>12.3f}")  # fmt: skip
        counts[group] = (flagged, len(results))
    (ft, nt), (fs, ns) = counts["typical"], counts["still"]
    print(f"typical clips with p > 0.05: published {nt - ft['published']} of {nt}, extended {nt - ft['extended']} "
          f"of {nt}, asymmetry {nt - ft['asymmetry']} of {nt}")  # fmt: skip
    print(f"still-left-arm clips with p < 0.05: published {fs['published']} of {ns}, extended {fs['extended']} of "
          f"{ns}, asymmetry {fs['asymmetry']} of {ns}")  # fmt: skip
    print(f"lifting took {lifted:.0f} s; fold {args.fold} prior {prior}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
