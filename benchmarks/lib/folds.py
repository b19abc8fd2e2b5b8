"""K-fold split of the 600 SyRIP training poses, for choosing lifting settings without Test100.

    python benchmarks/lib/folds.py --syrip-dir ../shared/data/syrip --out folds/   # writes the folds
    zedo fit-prior folds/fold0-train.npz --recipe weights_spec/syrip12-scratch.toml --out folds/fold0.safetensors

Each fold k holds out 150 training poses (a seeded permutation, seed 1234, cut into 4 parts):
`fold<k>-train.npz` has the other 450 poses (what `zedo fit-prior` reads) and
`fold<k>-held-out.json` the held-out image names. A prior trained on fold k's 450 poses lifts
fold k's 150 held-out poses (ground-truth and FiDIP 2D) as an unseen validation set. Test100
and the synthetic rows are never part of any fold.
"""

from __future__ import annotations

import argparse
import json
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

FOLD_SEED = 1234
FOLDS = 4


def fold_names(names: list[str], folds: int = FOLDS, seed: int = FOLD_SEED) -> list[list[str]]:
    """The held-out names of each fold: a seeded permutation of `names` cut into `folds` parts."""
    import numpy as np

    order = np.random.default_rng(seed).permutation(len(names))
    return [sorted(names[i] for i in part) for part in np.array_split(order, folds)]


def held_out_names(folder: Path, fold: int) -> list[str]:
    return json.loads((folder / f"fold{fold}-held-out.json").read_text())


def fold_priors(
    folder: Path, weights: str, syrip_dir: str | Path, only: Sequence[int] | None = None
) -> Iterator[tuple[int, Any, Any, dict]]:
    """For each fold (of `only`, default all) whose prior `fold<k><weights>.safetensors` exists in
    `folder`: the fold, its prior, the ground truth of its held-out poses and their 2D inputs
    ("gt", "detected")."""
    from zedo_cli.evaluation.syrip_benchmark import load_syrip_train_inputs
    from zedo_cli.prior.weights import load_prior

    for k in range(FOLDS) if only is None else only:
        path = folder / f"fold{k}{weights}.safetensors"
        if path.exists():
            truth, inputs = load_syrip_train_inputs(syrip_dir, held_out_names(folder, k))
            yield k, load_prior(path), truth, inputs


def fold_clip_args(doc: str, interpolation: str | None = None) -> argparse.Namespace:
    """The command line of a benchmark over the fold priors' synthetic clips: `--syrip-dir`, `--folds` and,
    where `interpolation` names its default, `--interpolation` (the clips' motion, temporal.make_sequences)."""
    ap = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    ap.add_argument("--syrip-dir", required=True)
    ap.add_argument("--folds", type=Path, required=True)
    if interpolation is not None:
        ap.add_argument("--interpolation", choices=("positions", "segments"), default=interpolation)
    return ap.parse_args()


def main() -> int:
    import numpy as np

    from zedo_cli.data.datasets import load_syrip_3d

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--syrip-dir", required=True)
    ap.add_argument("--out", type=Path, required=True)
    args = ap.parse_args()
    train = load_syrip_3d(args.syrip_dir, "train")
    args.out.mkdir(parents=True, exist_ok=True)
    for k, held in enumerate(fold_names(list(train.names))):
        keep = [i for i, n in enumerate(train.names) if n not in set(held)]
        names = np.array([train.names[i] for i in keep])
        np.savez(args.out / f"fold{k}-train.npz", poses=train.poses[keep], joint_names=np.array(train.skeleton.joints),
                 names=names)  # fmt: skip
        (args.out / f"fold{k}-held-out.json").write_text(json.dumps(held))
        print(f"fold {k}: {len(keep)} training poses, {len(held)} held out")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
