"""A tried and rejected remedy for the knee's clip mean angle (docs/movement.md, "What limits the knee's mean
angle"): a prior that has seen more legs pointing away from the camera.

`write`: per fold k of `--folds` (benchmarks/lib/folds.py), `fold<k>legs-train.npz`: the fold's 450 training poses
and a copy of each with one or both legs mirrored in depth about their hip (the knee's and the ankle's camera
z reflected through the hip's; each leg with probability 1/2, at least one; seed 7 + k). A mirrored leg keeps
its bone lengths, its knee angle and, orthographically, its 2D: it is the other solution of the depth
ambiguity that bends the lifted knee. Train a prior on each as on the fold's own poses:

    .venv/bin/python experiments/leg_depth_prior.py write --folds FOLDS
    zedo fit-prior FOLDS/fold<k>legs-train.npz --recipe weights_spec/syrip12-scratch.toml \
        -o FOLDS/fold<k>legs.safetensors

`score`: per weights suffix (`''`: the fold's own prior, `legs`: the one above), the fold's 150 held-out real
SyRIP images lifted from ground-truth and FiDIP 2D (default preset): MPJPE, PA-MPJPE, and the interior elbow
and knee angles' mean absolute and signed error against the weak 3D truth. The synthetic clips' side is
`features_3d_accuracy.py --weights legs`.

    .venv/bin/python experiments/leg_depth_prior.py score --syrip-dir ../shared/data/syrip --folds FOLDS \
        --weights '' legs

Test100 and SyRIP's synthetic rows are never read.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root
from benchmarks.lib.folds import FOLDS, fold_priors
from zedo_cli.analysis.pose.geometry import angle_between_deg

AUGMENT_SEED = 7
ANGLES = {"elbow": ("shoulder", "elbow", "wrist"), "knee": ("hip", "knee", "ankle")}


def mirror_legs(poses: np.ndarray, joints: list[str], rng: np.random.Generator) -> np.ndarray:
    """A copy of `poses (N, J, 3)` with each leg's knee and ankle depth reflected through its hip's, each leg
    with probability 1/2 and at least one per pose."""
    mirrored = rng.random((len(poses), 2)) < 0.5
    neither = ~mirrored.any(axis=1)
    mirrored[neither, rng.integers(0, 2, int(neither.sum()))] = True
    out = poses.copy()
    for s, side in enumerate(("left", "right")):
        hip = joints.index(f"{side}_hip")
        for joint in (f"{side}_knee", f"{side}_ankle"):
            j = joints.index(joint)
            out[mirrored[:, s], j, 2] = 2 * poses[mirrored[:, s], hip, 2] - poses[mirrored[:, s], j, 2]
    return out


def write(folder: Path) -> None:
    for k in range(FOLDS):
        with np.load(folder / f"fold{k}-train.npz") as data:
            poses, joints, names = data["poses"], data["joint_names"], data["names"]
        copies = mirror_legs(poses, [str(j) for j in joints], np.random.default_rng(AUGMENT_SEED + k))
        np.savez(folder / f"fold{k}legs-train.npz", poses=np.concatenate([poses, copies]), joint_names=joints,
                 names=np.concatenate([names, np.char.add(names, "-legs")]))  # fmt: skip
        print(f"fold {k}: {len(poses)} poses and {len(copies)} with mirrored legs -> fold{k}legs-train.npz")


def interior_angle(poses: np.ndarray, joints: list[str], side: str, angle: str) -> np.ndarray:
    """`(N,)` the interior angle in degrees at the middle joint of ANGLES[angle] on `side`."""
    a, b, c = (poses[:, joints.index(f"{side}_{name}")] for name in ANGLES[angle])
    return angle_between_deg(a - b, c - b)


def score(syrip_dir: str, folder: Path, suffixes: list[str]) -> None:
    import torch

    from zedo_cli.evaluation.syrip_benchmark import lift_and_score
    from zedo_cli.lifting.config import DEFAULT_PRESET, get_preset

    cfg = get_preset(DEFAULT_PRESET)
    print("| prior | fold | 2D | MPJPE | PA-MPJPE | elbow MAE | elbow signed | knee MAE | knee signed |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for suffix in suffixes:
        for k, prior, truth, inputs in fold_priors(folder, suffix, syrip_dir):
            joints = list(prior.skeleton.joints)
            for source in ("gt", "detected"):
                torch.manual_seed(0)
                result, lift = lift_and_score(prior, truth, inputs[source], cfg, input_2d=source)
                lifted = np.where(lift.lifted[:, None, None], lift.poses_camera, np.nan)
                cells = []
                for angle in ANGLES:
                    error = np.concatenate([interior_angle(lifted, joints, side, angle)
                                            - interior_angle(truth.poses, joints, side, angle)
                                            for side in ("left", "right")])  # fmt: skip
                    cells += [f"{np.nanmean(np.abs(error)):.2f}", f"{np.nanmean(error):+.2f}"]
                print(f"| fold{k}{suffix} | {k} | {source} | {result.mpjpe_mm:.2f} | {result.pa_mpjpe_mm:.2f} | "
                      + " | ".join(cells) + " |", flush=True)  # fmt: skip


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("step", choices=("write", "score"))
    ap.add_argument("--folds", type=Path, required=True)
    ap.add_argument("--syrip-dir", default="../shared/data/syrip")
    ap.add_argument("--weights", nargs="+", default=["", "legs"], help="score: the fold priors' file suffixes")
    args = ap.parse_args()
    if args.step == "write":
        write(args.folds)
    else:
        score(args.syrip_dir, args.folds, args.weights)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
