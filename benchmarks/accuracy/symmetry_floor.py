"""How low can a lift's symmetry-angle error go while it honours the 2D?

A lift with perfect depth: SyRIP's weak 3D ground truth is placed in the pseudo camera (its root
translation fitted to the rays of the 2D, as the lift places its poses), and every observed joint
is moved `w` of the way onto its camera ray (orthogonally, as the lift's ray step does), the
depth of every joint thus kept from the truth. Its symmetry-angle error against the truth is what
the disagreement of the 2D with the 3D truth alone costs: w = 1 is a lift that keeps joints on
their rays (the reference), w = 0.75 the softer rays of `fast`, w = 0 the truth itself (0).

Beside it, for scale: the constant yardstick (every pose gets each pair's median angle of the
600 training poses) and the 2D width of hips and shoulders against the truth's projected width.
Nothing is lifted and no prior is read, so nothing is chosen here; Test100 is read only with
`--split test`.

With `--errors DIR` (the per-pose lifts that `benchmarks/calibrate/lift_validation.py --errors DIR` saved
on held-out folds), the error of those lifts is split: the lifted x, y with the truth's depth,
and the truth's x, y with the lifted depth (root-relative camera frame, per input kind).

    python benchmarks/accuracy/symmetry_floor.py --syrip-dir ../shared/data/syrip [--split test]
    python benchmarks/accuracy/symmetry_floor.py --syrip-dir ../shared/data/syrip --errors folds/errors --variant fast
"""

from __future__ import annotations

import argparse
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch

from zedo_cli.data.skeleton import Skeleton

WEIGHTS = (1.0, 0.75, 0.5)


@dataclass
class TruthInCamera:
    """The root-relative truth `pose (N, J, 3)` placed in the pseudo camera of a 2D input: its
    translation `trans (N, 1, 3)` fitted to the rays `rays (N, J, 3)` (z = 1) of the `observed`
    joints, as the lift places a pose; `k (N, 3, 3)` the intrinsics."""

    pose: torch.Tensor
    trans: torch.Tensor
    rays: torch.Tensor
    observed: torch.Tensor
    k: torch.Tensor


def place_truth(poses: np.ndarray, kp) -> TruthInCamera:
    """`poses` placed in the pseudo camera of `kp`'s 2D (in the same joint order)."""
    from zedo_cli.lifting.camera import pixel_rays, resolve_intrinsics, solve_root_translation

    mats, _ = resolve_intrinsics(kp.image_sizes, kp.image_ids, kp.file_names)
    k = torch.as_tensor(mats, dtype=torch.float64)
    rays = pixel_rays(torch.as_tensor(np.nan_to_num(kp.xy), dtype=torch.float64), k)
    observed = torch.as_tensor(kp.confidence > 0)
    pose = torch.as_tensor(poses, dtype=torch.float64)
    trans = solve_root_translation(pose, rays, observed.double())[:, None]
    return TruthInCamera(pose, trans, rays, observed, k)


def truth_on_rays(placed: TruthInCamera, weight: float) -> np.ndarray:
    """The placed truth with each observed joint moved `weight` of the way onto its ray at fixed
    translation, and moved back by that translation (the root itself may move: fine for symmetry
    angles, which ignore translation)."""
    from zedo_cli.lifting.camera import project_onto_rays

    pose, trans = placed.pose, placed.trans
    unit = placed.rays / placed.rays.norm(dim=-1, keepdim=True)
    moved = torch.lerp(pose, project_onto_rays(pose + trans, unit) - trans, weight)
    return torch.where(placed.observed[..., None], moved, pose).numpy()


def width_ratio(placed: TruthInCamera, kp, joint: str) -> float:
    """Median over poses of the 2D distance of the left and right `joint` over the distance of
    the placed truth's two joints, projected."""
    from zedo_cli.lifting.camera import project

    names = kp.skeleton.joints
    left, right = names.index(f"left_{joint}"), names.index(f"right_{joint}")
    uv = project(placed.pose + placed.trans, placed.k).numpy()
    seen = (kp.confidence[:, left] > 0) & (kp.confidence[:, right] > 0)
    two_d = np.linalg.norm(kp.xy[:, left] - kp.xy[:, right], axis=-1)
    three_d = np.linalg.norm(uv[:, left] - uv[:, right], axis=-1)
    return float(np.median(two_d[seen] / three_d[seen]))


def depth_split(errors: Path, variant: str, skeleton: Skeleton) -> list[dict]:
    """Per input kind: the symmetry-angle error of the saved lifts of `variant`, as lifted, with
    the truth's depth, and with the truth's x, y."""
    from zedo_cli.evaluation.plausibility import symmetry_angle_error_deg

    def error(pose: np.ndarray, truth: np.ndarray) -> float:
        return round(symmetry_angle_error_deg(pose, truth, skeleton), 2)

    rows = []
    for kind in ("gt", "detected"):
        files = sorted(errors.glob(f"fold*-{variant}-{kind}.npz"))
        if not files:
            continue
        pose = np.concatenate([np.load(f)["pose"] for f in files])
        truth = np.concatenate([np.load(f)["truth"] for f in files])
        keep = np.isfinite(pose).all(axis=(1, 2))
        pose, truth = pose[keep], truth[keep]
        true_depth, lifted_depth = pose.copy(), truth.copy()
        true_depth[..., 2], lifted_depth[..., 2] = truth[..., 2], pose[..., 2]
        rows.append({"input": kind, "variant": variant, "files": len(files), "poses": len(pose),
                     "lifted_deg": error(pose, truth), "lifted_xy_true_depth_deg": error(true_depth, truth),
                     "true_xy_lifted_depth_deg": error(lifted_depth, truth)})  # fmt: skip
    return rows


def main() -> int:
    from zedo_cli.analysis.pose.symmetry import symmetry_angles
    from zedo_cli.data.datasets import load_syrip_3d
    from zedo_cli.evaluation.plausibility import symmetry_angle_error_deg
    from zedo_cli.evaluation.syrip_benchmark import load_benchmark_inputs, load_syrip_train_inputs

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--syrip-dir", required=True)
    ap.add_argument("--split", choices=("train", "test"), default="train",
                    help="train: the 600 training poses; test: Test100 (nothing is chosen by it)")  # fmt: skip
    ap.add_argument("--errors", type=Path, default=None, help="lift_validation.py's --errors folder")
    ap.add_argument("--variant", default="fast", help="the variant whose saved lifts --errors splits")
    args = ap.parse_args()
    train = load_syrip_3d(args.syrip_dir, "train")
    if args.split == "train":
        truth, inputs = load_syrip_train_inputs(args.syrip_dir, list(train.names))
    else:
        truth, inputs = load_benchmark_inputs(Path(args.syrip_dir))
    skeleton = truth.skeleton
    medians = {k: np.median(v) for k, v in symmetry_angles(train.poses, skeleton).items()}
    constant = np.mean([np.mean(np.abs(medians[k] - v)) for k, v in symmetry_angles(truth.poses, skeleton).items()])
    rows = []
    for kind, kp in inputs.items():
        kp = kp.to_skeleton(skeleton)
        placed = place_truth(truth.poses, kp)
        row = {"split": args.split, "input": kind, "poses": len(truth.poses),
               "hip_width_2d_over_3d": round(width_ratio(placed, kp, "hip"), 3),
               "shoulder_width_2d_over_3d": round(width_ratio(placed, kp, "shoulder"), 3),
               "constant_yardstick_deg": round(float(constant), 2)}  # fmt: skip
        for w in WEIGHTS:
            moved = truth_on_rays(placed, w)
            row[f"truth_on_rays_{w:g}_deg"] = round(symmetry_angle_error_deg(moved, truth.poses, skeleton), 2)
        rows.append(row)
        print(json.dumps(row))
    if args.errors is not None:
        for row in depth_split(args.errors, args.variant, skeleton):
            print(json.dumps(row))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
