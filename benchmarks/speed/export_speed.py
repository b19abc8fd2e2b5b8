"""Writing a long clip as TRC and C3D, against lifting it (docs/exports.md "Speed").

Builds a result of `--poses` poses, one person per frame at 30 fps with every 50th frame empty
and every 20th person not lifted (the bundled prior's poses, 1 cm of seeded jitter), then times
`write_result` to a TRC file and to a C3D file (and, for scale, to JSON). Then it lifts
`--lift` of those poses' projections with the bundled prior and the default preset, and reports
poses per second for each.

    .venv/bin/python benchmarks/speed/export_speed.py --poses 100000 --lift 2000 --workdir /tmp/zedo-export
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from zedo_cli.data.keypoints import Keypoints2D
from zedo_cli.data.skeleton import root_point
from zedo_cli.formats.writers.outputs import write_result
from zedo_cli.lifting.config import LiftConfig, get_preset
from zedo_cli.lifting.solver import LiftResult, lift
from zedo_cli.prior.weights import load_prior, resolve_prior_path

K = np.array([[1000.0, 0.0, 320.0], [0.0, 1000.0, 240.0], [0.0, 0.0, 1.0]])


def make_result(poses: int, seed: int) -> tuple[Keypoints2D, LiftResult]:
    prior = load_prior(resolve_prior_path(None))
    template = prior.template.cpu().numpy()  # (J, 3) root-relative metres
    rng = np.random.default_rng(seed)
    cam = template[None] + rng.normal(0.0, 0.01, (poses, len(template), 3)) + np.array([0.0, 0.0, 1.2])
    uv = cam @ K.T
    xy = uv[..., :2] / uv[..., 2:]
    n, j = cam.shape[:2]
    lifted = np.arange(n) % 20 != 7
    cam[~lifted] = np.nan
    frames = [i + i // 49 for i in range(n)]  # every 50th frame number has no person
    kp = Keypoints2D(xy, np.full((n, j), 0.9), prior.skeleton, frames, [None] * n, np.full((n, 2), [640.0, 480.0]),
                     [None] * n, "bench.jsonl", "zedo-jsonl", frames)  # fmt: skip
    root = root_point(cam, prior.skeleton)
    res = LiftResult(cam, cam - root[:, None], root, np.full((n, j), 1.0), np.ones((n, j), bool), lifted,
                     LiftConfig(), 0.0)  # fmt: skip
    return kp, res


def time_write(workdir: Path, kp: Keypoints2D, res: LiftResult, fmt: str) -> float:
    mats = np.broadcast_to(K, (len(kp), 3, 3))
    start = time.perf_counter()
    write_result(workdir / f"clip.{fmt}", kp, res, mats, ["cli"] * len(kp), {"fps": 30.0}, {"path": "bench"},
                 overwrite=True)  # fmt: skip
    return time.perf_counter() - start


def time_lift(kp: Keypoints2D, count: int) -> float:
    prior = load_prior(resolve_prior_path(None))
    xy = kp.xy[:count]
    start = time.perf_counter()
    lift(xy, kp.confidence[:count], np.broadcast_to(K, (count, 3, 3)).copy(), prior, get_preset("fast"))
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--poses", type=int, default=100_000)
    parser.add_argument("--lift", type=int, default=2000, help="poses to lift for the comparison (0: none)")
    parser.add_argument("--workdir", type=Path, default=Path("/tmp/zedo-export-speed"))
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument(
        "--formats", nargs="*", default=["trc", "c3d", "json"], help="formats to write (none: lift only)"
    )
    args = parser.parse_args()
    args.workdir.mkdir(parents=True, exist_ok=True)
    kp, res = make_result(args.poses, args.seed)
    report = {"poses": args.poses}
    for fmt in args.formats:
        seconds = time_write(args.workdir, kp, res, fmt)
        size = (args.workdir / f"clip.{fmt}").stat().st_size
        report[fmt] = {
            "seconds": round(seconds, 2),
            "poses_per_s": round(args.poses / seconds),
            "mb": round(size / 1e6, 1),
        }
        print(f"{fmt:5s} {seconds:7.2f} s  {args.poses / seconds:9.0f} poses/s  {size / 1e6:6.1f} MB", flush=True)
    if args.lift:
        seconds = time_lift(kp, args.lift)
        report["lift"] = {"poses": args.lift, "seconds": round(seconds, 2), "poses_per_s": round(args.lift / seconds)}
        print(f"lift  {seconds:7.2f} s  {args.lift / seconds:9.0f} poses/s  ({args.lift} poses, preset fast)")
    print(json.dumps(report))
    for fmt in args.formats:
        (args.workdir / f"clip.{fmt}").unlink()


if __name__ == "__main__":
    main()
