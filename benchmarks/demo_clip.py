"""A synthetic infant clip as a detector would stream it: zedo JSON Lines 2D of one 30 fps clip
made from SyRIP *training* poses (benchmarks/temporal.py's generator: key poses eased 1 s apart,
the body turning and drifting, 3 px noise, 3 % dropped joints), for trying `zedo lift --temporal`
and `zedo analyze` on a video (docs/clinical.md's clip report was made with it):

    python benchmarks/demo_clip.py --syrip-dir ../shared/data/syrip --out clip.jsonl
    zedo lift clip.jsonl --skeleton syrip12 --fps 30 --temporal smooth -o clip.zedo.json
    zedo analyze clip.zedo.json --report report/

SyRIP's terms (non-commercial research) hold for the file. Test100 and the synthetic rows are
never read.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
from temporal import IMAGE_H, IMAGE_W, make_sequences

from zedo_cli.data.datasets import load_syrip_3d


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
    clip = make_sequences(train.poses, np.random.default_rng(args.seed), count=1, keyposes=args.keyposes,
                          transition_s=1.0, fps=30.0, noise_px=3.0, drop=0.03, gap=0)  # fmt: skip
    with args.out.open("w") as f:
        for i, (xy, conf) in enumerate(zip(clip["xy"], clip["conf"], strict=True)):
            points = [[round(float(x), 2), round(float(y), 2), float(c)] for (x, y), c in zip(xy, conf, strict=True)]
            record = {"frame": i, "persons": [{"keypoints": points}]}
            if i == 0:
                record["image_size"] = [IMAGE_W, IMAGE_H]
            f.write(json.dumps(record) + "\n")
    print(f"wrote {args.out}: {len(clip['xy'])} frames at 30 fps, {IMAGE_W}x{IMAGE_H}, syrip12 joints")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
