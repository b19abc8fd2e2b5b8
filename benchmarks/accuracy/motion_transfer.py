"""Do the frame-level measure calibrations of `--temporal smooth` hold on clips whose bones keep their length?

calibrate_measures.py fits the smooth-mode measure calibration on clips that ease every joint's position
between key poses (temporal.make_sequences, `interpolation="positions"`), which shortens a turning bone.
Per fold prior in `--folds`, this lifts calibrate_measures.py's clips (16 clips of 5 s, seed 100 + k) under
both motions, `positions` and `segments` (one infant's bones kept, each segment turned), in `--temporal
smooth` with the default preset, and scores each fold's clips with the models fitted on the other fold's:
fitted on `positions` clips only (as shipped) and on both. It prints the coverage of the 90 % intervals over
every measure (cases pooled) and over the symmetry pairs, and the five measures of least coverage, per motion
scored. Test100 and SyRIP's synthetic rows are never read.

    OMP_NUM_THREADS=2 .venv/bin/python benchmarks/accuracy/motion_transfer.py --syrip-dir ../shared/data/syrip \\
        --folds FOLDS
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np
import torch

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the repository root
from benchmarks.calibrate.calibrate_measures import BINS, SYMMETRY_NAMES, case_arrays, fit_all, load_cases, scored
from benchmarks.lib.folds import fold_priors
from benchmarks.lib.settings import CLIP_SETTINGS
from zedo_cli.analysis.pose.symmetry import DEFAULT_THRESHOLD_DEG
from zedo_cli.evaluation.clips.eased import make_sequences
from zedo_cli.lifting.config import DEFAULT_PRESET, get_preset
from zedo_cli.lifting.temporal import lift_sequence

MOTIONS = ("positions", "segments")


def lift_clips(folder: Path, folds: Path, syrip_dir: str) -> None:
    cfg = get_preset(DEFAULT_PRESET)
    for k, prior, truth, _ in fold_priors(folds, "", syrip_dir):
        for motion in MOTIONS:
            torch.manual_seed(k)
            clips = make_sequences(truth.poses, np.random.default_rng(100 + k), **CLIP_SETTINGS, interpolation=motion)
            res = lift_sequence(clips["xy"], clips["conf"], clips["k"], prior, cfg, mode="smooth",
                                tracks=clips["tracks"])  # fmt: skip
            arrays = case_arrays(res.poses_root_relative, res.observed, res.lifted, clips["rel"])
            np.savez(folder / f"fold{k}-smooth-{motion}.npz", group=clips["tracks"], **arrays)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--syrip-dir", required=True)
    ap.add_argument("--folds", type=Path, required=True)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        lift_clips(Path(tmp), args.folds, args.syrip_dir)
        cases, fold, motion, _ = load_cases(Path(tmp), "smooth")
    if len(np.unique(fold)) < 2:
        print(f"need two fold priors fold<k>.safetensors in {args.folds}", file=sys.stderr)
        return 1
    print("| fitted on | scored on | coverage, every measure | symmetry pairs | least covered |")
    print("| --- | --- | --- | --- | --- |")
    for fit_on in (MOTIONS[:1], MOTIONS):
        held = [(fit_all(cases, (fold != f) & np.isin(motion, fit_on), BINS["smooth"]), fold == f)
                for f in np.unique(fold)]  # fmt: skip
        for scored_on, rows in scored(held, cases, motion, DEFAULT_THRESHOLD_DEG).items():
            weights = np.array([r["cases"] for r in rows.values()])
            coverage = np.array([r["coverage_0.9"] for r in rows.values()])
            sym = np.mean([rows[n]["coverage_0.9"] for n in SYMMETRY_NAMES if n in rows])
            least = ", ".join(f"{n} {r['coverage_0.9']:.1%}" for n, r in
                              sorted(rows.items(), key=lambda x: x[1]["coverage_0.9"])[:5])  # fmt: skip
            print(f"| {' + '.join(fit_on)} | {scored_on} | {np.average(coverage, weights=weights):.1%} | {sym:.1%} "
                  f"| {least} |")  # fmt: skip
    return 0


if __name__ == "__main__":
    sys.exit(main())
