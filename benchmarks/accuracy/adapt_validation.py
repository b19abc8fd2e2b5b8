"""Choose an adaptation schedule without looking at Test100: adapt on a seeded subset of S SyRIP
training poses, lift 150 *other* training poses (held out of the subset; ground-truth 2D, and
FiDIP-detected 2D too with --inputs gt detected; `fast` preset) with snapshots of the raw and EMA
weights taken during one training, and score them.

    python benchmarks/accuracy/adapt_validation.py --syrip-dir ../shared/data/syrip --strategy scratch \\
        --size 20 --subset-seeds 100 101 102 --snapshots 1000 2000 4000 8000 --warmup 5000 --out val.jsonl
    python benchmarks/accuracy/adapt_validation.py --syrip-dir ../shared/data/syrip --strategy finetune \\
        --size 450 --add-poses aug.npz --snapshots 1000 --out val.jsonl
    python benchmarks/accuracy/adapt_validation.py --syrip-dir ../shared/data/syrip --strategy finetune \\
        --size 450 --subset-seeds 100 --write-subsets subsets --out val.jsonl

The held-out poses are drawn (seed 1234) from the training poses outside the subset, so S can be
at most 600 - --held-out. Every run appends one JSON line to --out (an interrupted sweep resumes);
the summary gives, per snapshot, the mean held-out MPJPE over subset seeds. Runs go to --jobs
worker processes, one CPU thread each. Subset seeds default to 100+ so they never coincide with
the seeds of the published table (0, 1, 2).
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the repository root
from benchmarks.lib.resumable_runs import read_rows, run_and_record

HELD_OUT_SEED = 1234
SCORE_FIELDS = {"gt": "held_out_mpjpe_mm", "detected": "held_out_detected_mpjpe_mm"}


def run_one(job: dict) -> dict:
    import numpy as np
    import torch

    torch.set_num_threads(1)
    from zedo_cli.data.datasets import load_npz_poses, load_syrip_3d
    from zedo_cli.evaluation.syrip_benchmark import lift_and_score, load_syrip_train_inputs
    from zedo_cli.lifting.config import PRESETS
    from zedo_cli.prior.adapt import adapt_prior, in_memory_prior, select_subset, with_added_poses
    from zedo_cli.prior.schedules import default_training
    from zedo_cli.prior.weights import load_prior, resolve_prior_path

    base = load_prior(resolve_prior_path(job["base"]))
    train = load_syrip_3d(job["syrip_dir"], "train")
    subset = select_subset(train, job["size"], job["subset_seed"])
    chosen = set(subset.names)
    rest = [n for n in train.names if n not in chosen]
    rows = np.sort(np.random.default_rng(HELD_OUT_SEED).choice(len(rest), job["held_out"], replace=False))
    truth, inputs = load_syrip_train_inputs(job["syrip_dir"], [rest[i] for i in rows])
    data = subset
    if job.get("added"):
        data = with_added_poses(subset, load_npz_poses(job["added"], train.skeleton.name))

    snapshots: dict[str, dict] = {}

    def keep_snapshots(progress) -> None:
        if progress.epoch in job["snapshots"]:
            for weights in ("raw", "ema"):
                snapshots[f"{weights}@{progress.epoch}"] = progress.snapshot(weights)

    cfg = replace(default_training(job["strategy"]), epochs=max(job["snapshots"]), warmup_steps=job["warmup"],
                  lr=job["lr"], seed=job["subset_seed"])  # fmt: skip
    adapted = adapt_prior(base, data, job["strategy"], cfg, callback=keep_snapshots)
    scores: dict[str, dict[str, float]] = {kind: {} for kind in job["inputs"]}
    for name, state in snapshots.items():
        prior = in_memory_prior(adapted, base, data, state)
        for kind in scores:
            score, _ = lift_and_score(prior, truth, inputs[kind], PRESETS[job["preset"]])
            scores[kind][name] = round(score.mpjpe_mm, 2)
    return {**job, "train_seconds": round(adapted.result.seconds, 1),
            **{SCORE_FIELDS[kind]: values for kind, values in scores.items()}}  # fmt: skip


def write_subsets(syrip_dir: str, size: int, seeds: list[int], folder: Path) -> list[Path]:
    """Each seed's subset of the SyRIP training poses as an npz that `zedo augment --infant` reads."""
    import numpy as np

    from zedo_cli.data.datasets import load_syrip_3d
    from zedo_cli.prior.adapt import select_subset

    train = load_syrip_3d(syrip_dir, "train")
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for seed in seeds:
        subset = select_subset(train, size, seed)
        path = folder / f"subset-S{size}-seed{seed}.npz"
        np.savez(path, poses=subset.poses, joint_names=np.array(subset.skeleton.joints), names=np.array(subset.names))
        paths.append(path)
    return paths


def summarise(rows: list[dict], kind: str) -> str:
    field = SCORE_FIELDS[kind]
    keys = sorted({k for r in rows for k in r[field]}, key=lambda k: (int(k.split("@")[1]), k))
    lines = [f"| snapshot | runs | held-out MPJPE, {kind} 2D (mm), mean ± sd | per subset seed |",
             "| --- | --- | --- | --- |"]  # fmt: skip
    for key in keys:
        values = [r[field][key] for r in rows if key in r[field]]
        sd = f" ± {statistics.stdev(values):.1f}" if len(values) > 1 else ""
        per_run = " / ".join(f"{v:.1f}" for v in values)
        lines.append(f"| {key} | {len(values)} | {statistics.mean(values):.1f}{sd} | {per_run} |")
    return "\n".join(lines)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--syrip-dir", required=True)
    ap.add_argument("--base", default="adult12-rotscale", help="base prior: bundled name or file")
    ap.add_argument("--strategy", choices=("control", "finetune", "scratch"), required=True)
    ap.add_argument("--size", type=int, required=True, help="training poses in the subset (S)")
    ap.add_argument("--subset-seeds", nargs="+", type=int, default=[100, 101, 102])
    ap.add_argument("--snapshots", nargs="+", type=int, default=[1000], help="epochs at which to score")
    ap.add_argument("--warmup", type=int, default=None, help="warm-up steps (default: the strategy's recipe)")
    ap.add_argument("--lr", type=float, default=None, help="learning rate (default: the strategy's recipe)")
    ap.add_argument("--held-out", type=int, default=150, help="training poses outside the subset to score")
    ap.add_argument("--add-poses", default=None, help="npz of poses added to the subset (e.g. zedo augment's)")
    ap.add_argument("--preset", default="fast")
    ap.add_argument("--inputs", nargs="+", choices=tuple(SCORE_FIELDS), default=["gt"], help="2D inputs to score")
    ap.add_argument("--out", type=Path, required=True, help="JSON lines, appended (resumes)")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--write-subsets", type=Path, default=None, metavar="DIR",
                    help="only write each subset's poses to DIR/subset-S<size>-seed<seed>.npz (references for "
                         "`zedo augment --infant` that leave the held-out poses out) and stop")  # fmt: skip
    args = ap.parse_args()
    from zedo_cli.prior.schedules import default_training

    if args.size + args.held_out > 600:
        ap.error(f"--size {args.size} + --held-out {args.held_out} exceeds SyRIP's 600 training poses")
    if args.write_subsets is not None:
        for path in write_subsets(args.syrip_dir, args.size, args.subset_seeds, args.write_subsets):
            print(f"wrote {path}", file=sys.stderr)
        return 0
    done = read_rows(args.out)
    for row in done:
        row.setdefault("inputs", ["gt"])  # runs recorded before --inputs scored ground-truth 2D only
    fields = ("strategy", "size", "subset_seed", "snapshots", "warmup", "lr", "base", "added", "held_out", "preset")
    key = lambda r: json.dumps([r.get(f) for f in fields + ("inputs",)])  # noqa: E731
    have = {key(r) for r in done}
    recipe = default_training(args.strategy)
    settings = {"strategy": args.strategy, "size": args.size, "base": args.base, "added": args.add_poses,
                "warmup": recipe.warmup_steps if args.warmup is None else args.warmup,
                "lr": recipe.lr if args.lr is None else args.lr, "held_out": args.held_out,
                "preset": args.preset, "inputs": sorted(set(args.inputs), key=list(SCORE_FIELDS).index)}  # fmt: skip
    jobs = []
    for seed in args.subset_seeds:
        job = {**settings, "subset_seed": seed, "snapshots": sorted(set(args.snapshots)), "syrip_dir": args.syrip_dir}
        if key(job) not in have:
            jobs.append(job)
    print(f"{len(jobs)} runs to do, {len(done)} already in {args.out}", file=sys.stderr)
    start = time.time()
    for row in run_and_record(run_one, jobs, args.out, args.jobs):
        done.append(row)
        scores = {kind: row[SCORE_FIELDS[kind]] for kind in row["inputs"]}
        print(f"[{time.time() - start:6.0f} s] {row['strategy']} S={row['size']} subset seed "
              f"{row['subset_seed']}: {scores}", file=sys.stderr, flush=True)  # fmt: skip
    mine = [r for r in done if all(r.get(f) == v for f, v in settings.items())]
    for kind in settings["inputs"]:
        print(summarise(mine, kind))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
