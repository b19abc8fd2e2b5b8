"""The paper's few-shot SyRIP table (its Table 3): adapt a base prior with `control`,
`finetune` and `scratch` on S = 20, 100 and all 600 training poses, lift Test100 and score it.

S < 600 rows use one seeded subset per seed (the seed also drives the new weights, noise and
shuffling); the full-set row has one run per seed too. Every finished run is appended to
--out as one JSON line, so an interrupted table resumes where it stopped. --add-poses adds
poses (e.g. `zedo augment`'s) to every training set: the paper's "augmented" rows.

    python benchmarks/accuracy/adapt_table.py --syrip-dir ../shared/data/syrip --out adapt_table.jsonl
    python benchmarks/accuracy/adapt_table.py --syrip-dir ../shared/data/syrip --sizes 600 --add-poses aug.npz \\
        --out aug.jsonl

Runs go to --jobs worker processes, one CPU thread each.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the repository root
from benchmarks.lib.resumable_runs import read_rows, run_and_record

PAPER = {  # SyRIP Test100 MPJPE (mm), GT 2D, the paper's Table 3
    "control": {20: 67.8, 100: 56.4, 600: 49.4},
    "finetune": {20: 69.4, 100: 60.8, 600: 47.7},
    "scratch": {20: 72.3, 100: 60.6, 600: 54.0},
}
PAPER_AUGMENTED = {"control": 43.6, "finetune": 45.5, "scratch": 48.9}  # S = 600 + 600 augmented


def run_one(job: dict) -> dict:
    import torch

    torch.set_num_threads(1)
    from zedo_cli.data.datasets import load_npz_poses, load_syrip_3d
    from zedo_cli.evaluation.syrip_benchmark import lift_and_score, load_benchmark_inputs
    from zedo_cli.lifting.config import PRESETS
    from zedo_cli.prior.adapt import adapt_prior, in_memory_prior, select_subset, with_added_poses
    from zedo_cli.prior.schedules import default_training
    from zedo_cli.prior.weights import load_prior, resolve_prior_path

    base = load_prior(resolve_prior_path(job["base"]))
    train = load_syrip_3d(job["syrip_dir"], "train")
    size = job["size"]
    data = select_subset(train, None if size >= len(train.names) else size, job["seed"])
    if job.get("added"):
        data = with_added_poses(data, load_npz_poses(job["added"], train.skeleton.name))
    cfg = replace(default_training(job["strategy"]), epochs=job["epochs"], warmup_steps=job["warmup"], seed=job["seed"])
    adapted = adapt_prior(base, data, job["strategy"], cfg)
    prior = in_memory_prior(adapted, base, data, adapted.result.state(job["weights"]))
    truth, kps = load_benchmark_inputs(Path(job["syrip_dir"]))
    scores = {}
    for key in ("gt", "detected"):
        score, _ = lift_and_score(prior, truth, kps[key], PRESETS[job["preset"]], input_2d=key)
        scores[key] = {"mpjpe_mm": round(score.mpjpe_mm, 2), "pa_mpjpe_mm": round(score.pa_mpjpe_mm, 2)}
    return {**job, "train_seconds": round(adapted.result.seconds, 1), "steps": adapted.result.steps,
            "trainable_parameters": adapted.trainable, "scores": scores}  # fmt: skip


def paper_figure(strategy: str, size: int, added: str | None) -> str:
    figure = PAPER_AUGMENTED.get(strategy) if added and size >= 600 else PAPER[strategy].get(size)
    return "—" if figure is None else str(figure)


def summarise(rows: list[dict]) -> str:
    lines = [
        "| strategy | S | runs | Test100 GT 2D MPJPE (mm), mean ± sd | per run | detected 2D mean "
        "| paper (GT) | train s / run |",
        "| --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for strategy in PAPER:
        for size in sorted({r["size"] for r in rows}):
            runs = [r for r in rows if r["strategy"] == strategy and r["size"] == size]
            if not runs:
                continue
            gt = [r["scores"]["gt"]["mpjpe_mm"] for r in runs]
            dt = [r["scores"]["detected"]["mpjpe_mm"] for r in runs]
            sd = f" ± {statistics.stdev(gt):.1f}" if len(gt) > 1 else ""
            secs = statistics.mean(r["train_seconds"] for r in runs)
            lines.append(
                f"| {strategy} | {size} | {len(runs)} | {statistics.mean(gt):.1f}{sd} | "
                f"{' / '.join(f'{g:.1f}' for g in gt)} | {statistics.mean(dt):.1f} | "
                f"{paper_figure(strategy, size, runs[0].get('added'))} | {secs:.0f} |"
            )
    return "\n".join(lines)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--syrip-dir", required=True)
    ap.add_argument("--base", default="adult12-rotscale", help="base prior: bundled name or file")
    ap.add_argument("--out", type=Path, required=True, help="JSON lines, appended (resumes)")
    ap.add_argument("--strategies", nargs="+", default=list(PAPER))
    ap.add_argument("--sizes", nargs="+", type=int, default=[20, 100, 600])
    ap.add_argument("--seeds", nargs="+", type=int, default=[0, 1, 2])
    ap.add_argument("--full-seeds", nargs="+", type=int, default=[0, 1, 2], help="seeds of the S=600 rows")
    ap.add_argument("--epochs", type=int, default=None, help="default: each strategy's recipe (zedo adapt's)")
    ap.add_argument("--warmup", type=int, default=None, help="warm-up steps; default: each strategy's recipe")
    ap.add_argument("--weights", choices=("raw", "ema"), default="raw")
    ap.add_argument("--preset", default="fast")
    ap.add_argument("--add-poses", default=None, help="npz of poses added to every training set")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--report", action="store_true", help="only print the table of the runs already in --out")
    args = ap.parse_args()
    from zedo_cli.prior.schedules import default_training

    def schedule(strategy: str) -> tuple[int, int]:
        """Epochs and warm-up steps of `strategy`'s runs: its recipe's unless given."""
        recipe = default_training(strategy)
        return args.epochs or recipe.epochs, recipe.warmup_steps if args.warmup is None else args.warmup

    done = read_rows(args.out)
    fields = ("strategy", "size", "seed", "epochs", "warmup", "weights", "base", "preset", "added")
    key = lambda r: tuple(r.get(f) for f in fields)  # noqa: E731
    have = {key(r) for r in done}
    jobs = []
    for size in args.sizes:
        for strategy in args.strategies:
            for seed in args.full_seeds if size >= 600 else args.seeds:
                job = {"strategy": strategy, "size": size, "seed": seed, "base": args.base,
                       "epochs": schedule(strategy)[0], "warmup": schedule(strategy)[1],
                       "weights": args.weights,
                       "preset": args.preset, "syrip_dir": args.syrip_dir, "added": args.add_poses}  # fmt: skip
                if key(job) not in have:
                    jobs.append(job)
    if args.report:
        jobs = []
    print(f"{len(jobs)} runs to do, {len(done)} already in {args.out}", file=sys.stderr)
    start = time.time()
    for row in run_and_record(run_one, sorted(jobs, key=lambda j: -j["size"]), args.out, args.jobs):
        done.append(row)
        print(f"[{time.time() - start:6.0f} s] {row['strategy']:8s} S={row['size']:<3d} "
              f"seed {row['seed']}: "
              f"GT {row['scores']['gt']['mpjpe_mm']:.1f} mm, "
              f"detected {row['scores']['detected']['mpjpe_mm']:.1f} mm "
              f"({row['train_seconds']:.0f} s training)", file=sys.stderr, flush=True)  # fmt: skip

    def this_setting(row: dict) -> bool:  # the rows this command's settings would produce
        return (row["base"], row["weights"], row.get("added"), row["epochs"], row.get("warmup")) == (
            args.base, args.weights, args.add_poses, *schedule(row["strategy"]))  # fmt: skip

    print(summarise([r for r in done if this_setting(r)]))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
