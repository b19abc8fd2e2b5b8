"""A synthetic infant clip as a detector would stream it: zedo JSON Lines 2D of one 30 fps clip
made from SyRIP *training* poses (zedo_cli/evaluation/clips/eased.py's generator: key poses eased 1 s apart,
the body turning and drifting, 3 px noise, 3 % dropped joints), for trying `zedo lift --temporal`
and `zedo analyze` on a video:

    python benchmarks/clips/demo_clip.py --syrip-dir ../shared/data/syrip --out clip.jsonl
    zedo lift clip.jsonl --fps 30 --temporal smooth -o clip.zedo.json
    zedo analyze clip.zedo.json --report report/

The infant stays inside the 1280x720 frame: the generator's calibration geometry (1 m from the
2000 px pseudo camera, drifting up to 35 cm) overfills it, so the clip stands at the nearest depth
(in 25 cm steps) at which every keypoint of every frame lies 20 px inside the frame, drifting a
fifth as much; the depth is printed. The first line names the joint set (`"skeleton": "syrip12"`),
so no `--skeleton` is needed. For a clip with footage to draw over, run examples/infant_clip_demo.py
(no data needed). SyRIP's terms (non-commercial research) hold for the file. Test100 and the
synthetic rows are never read.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the repository root
from zedo_cli.data.datasets import load_syrip_3d
from zedo_cli.evaluation.clips.eased import IMAGE_H, IMAGE_W, make_sequences

MARGIN_PX = 20.0
DRIFT_SCALE = 0.2


def inside(xy: np.ndarray) -> bool:
    """Every known keypoint `(T, J, 2)` at least MARGIN_PX inside the frame."""
    known = xy[np.isfinite(xy).all(-1)]
    return bool(((known >= MARGIN_PX) & (known <= np.array([IMAGE_W, IMAGE_H]) - MARGIN_PX)).all())


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--syrip-dir", required=True)
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--keyposes", type=int, default=8)
    args = ap.parse_args()
    if args.out.exists():
        raise SystemExit(f"{args.out}: already exists")
    train = load_syrip_3d(args.syrip_dir, "train")
    for depth in np.arange(1.0, 6.01, 0.25):  # the same poses and motion at each depth: the same seed
        clip = make_sequences(train.poses, np.random.default_rng(args.seed), count=1, keyposes=args.keyposes,
                              transition_s=1.0, fps=30.0, noise_px=3.0, drop=0.03, gap=0, depth_m=float(depth),
                              drift_scale=DRIFT_SCALE)  # fmt: skip
        if inside(clip["xy"]):
            break
    else:
        raise SystemExit("no depth up to 6 m keeps the clip inside the frame")
    with args.out.open("w") as f:
        for i, (xy, conf) in enumerate(zip(clip["xy"], clip["conf"], strict=True)):
            points = [None if c == 0 else [round(float(x), 2), round(float(y), 2), float(c)]
                      for (x, y), c in zip(xy, conf, strict=True)]  # fmt: skip
            record: dict = {"frame": i, "persons": [{"keypoints": points}]}
            if i == 0:
                record |= {"image_size": [IMAGE_W, IMAGE_H], "skeleton": "syrip12"}
            f.write(json.dumps(record) + "\n")
    known = clip["xy"][np.isfinite(clip["xy"]).all(-1)]
    print(f"wrote {args.out}: {len(clip['xy'])} frames at 30 fps, {IMAGE_W}x{IMAGE_H}, syrip12 joints; the infant "
          f"{depth:.2f} m from the camera, keypoints within x {known[:, 0].min():.0f}..{known[:, 0].max():.0f} px, "
          f"y {known[:, 1].min():.0f}..{known[:, 1].max():.0f} px")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
