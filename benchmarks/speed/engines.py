"""Throughput of `zedo lift` with the local engine and with `--engine ray` on one machine.

Writes `--files` COCO annotation files of `--poses` poses each (the six poses of
examples/prior_samples_coco.json, repeated with 1 px of seeded pixel jitter so no two are
equal), then runs, as a user would, in a fresh process each:

    zedo lift WORKDIR/in --output-dir WORKDIR/local --quiet
    zedo lift WORKDIR/in --output-dir WORKDIR/ray --quiet --engine ray [--workers N]

and reports wall time and poses per second for each, then checks that both engines wrote the
same files (equal apart from the creation time and the lifting seconds).

    .venv/bin/python benchmarks/speed/engines.py --workdir /tmp/zedo-engines --files 100 --poses 1000
"""

from __future__ import annotations

import argparse
import json
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "prior_samples_coco.json"
TIMINGS = re.compile(r'"(created|seconds)": [^,\n]*')


def write_inputs(folder: Path, files: int, poses: int, seed: int) -> None:
    base = json.loads(EXAMPLE.read_text())
    rng = np.random.default_rng(seed)
    anns = base["annotations"]
    for f in range(files):
        images, annotations = [], []
        for i in range(poses):
            src = anns[i % len(anns)]
            kp = np.asarray(src["keypoints"], dtype=float).reshape(-1, 3)
            seen = kp[:, 2] > 0
            kp[seen, :2] += rng.normal(0.0, 1.0, (int(seen.sum()), 2))
            image = dict(next(im for im in base["images"] if im["id"] == src["image_id"]), id=i, file_name=f"{i}.png")
            images.append(image)
            annotations.append({**src, "id": i, "image_id": i, "keypoints": np.round(kp, 3).ravel().tolist()})
        doc = {**base, "images": images, "annotations": annotations}
        (folder / f"clip{f:03d}.json").write_text(json.dumps(doc))


def run(args: list[str]) -> float:
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "zedo_cli", "lift", *args], capture_output=True, text=True)
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        raise SystemExit(f"zedo lift {' '.join(args)} failed ({done.returncode}):\n{done.stderr[-2000:]}")
    return seconds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--workdir", type=Path, required=True, help="emptied and filled with inputs and outputs")
    parser.add_argument("--files", type=int, default=100)
    parser.add_argument("--poses", type=int, default=1000, help="poses per file")
    parser.add_argument("--workers", type=int, default=None, help="--workers of the Ray run (default: one per CPU)")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    shutil.rmtree(args.workdir, ignore_errors=True)
    inputs = args.workdir / "in"
    inputs.mkdir(parents=True)
    write_inputs(inputs, args.files, args.poses, args.seed)
    total = args.files * args.poses
    rows = []
    for engine in ("local", "ray"):
        out = args.workdir / engine
        out.mkdir()
        extra = (
            ["--engine", "ray"] + (["--workers", str(args.workers)] if args.workers else []) if engine == "ray" else []
        )
        seconds = run([str(inputs), "--output-dir", str(out), "--quiet", *extra])
        rows.append((engine, seconds))
    local = {p.name: TIMINGS.sub("", p.read_text()) for p in (args.workdir / "local").iterdir()}
    on_ray = {p.name: TIMINGS.sub("", p.read_text()) for p in (args.workdir / "ray").iterdir()}
    same = local == on_ray and len(local) == args.files
    print(f"{args.files} files x {args.poses} poses = {total} poses")
    print("| engine | wall s | poses/s |")
    print("| --- | --- | --- |")
    for engine, seconds in rows:
        print(f"| {engine} | {seconds:.1f} | {total / seconds:.0f} |")
    print(f"outputs identical apart from timings: {same}")
    if not same:
        raise SystemExit(1)


if __name__ == "__main__":
    main()
