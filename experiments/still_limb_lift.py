"""Where the lift's movement of a still limb comes from: a held arm's elbow speed, true and lifted, per lift and per
oracle.

Clips: SyRIP training poses eased 1 s apart with bones of one length (`make_sequences(interpolation="segments")`),
the left upper arm and forearm held at their first frame's direction in the trunk's frame (a rigid arm that moves
with the shoulder), 3 px jitter, 3 % of joints dropped, 30 fps, the pseudo camera. Each pose in its own photo's
orientation, or with `--supine` turned chest to the camera and swaying about one place (the `-supine` sources of
`benchmarks/accuracy/norms_false_alarms.py`). Printed: the median over clips of the held (left) and moving (right)
elbow's `3d_median_vel_angle` for the truth, `--temporal smooth`, `two-pass` and `clip`, and for clip mode's limbs
rebuilt on the rays (`clip.solve_limbs`, not smoothed) with

- `clip limbs`: the estimated torso and bone lengths, sides by clip mode's Viterbi pass;
- `true torso and lengths`: the true torso and bone lengths in place of the estimates;
- `... + sides kept in the trunk frame`: the same, and each change of a bone's direction in the trunk's frame
  between frames costing `--continuity` per unit (a still limb keeps its direction there; its mirror image does not
  as the body turns);
- `estimated torso + sides kept in the trunk frame`: that cost with the estimated torso and lengths;
- `true torso and lengths, true sides`: each joint on the solution nearer the truth.

    python experiments/still_limb_lift.py --syrip-dir ../shared/data/syrip [--supine] [--clips 8]
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root
from benchmarks.lib.pose_sources import eased_source_poses
from zedo_cli.analysis.clip.features_3d import features_3d
from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.evaluation.clips.cameras import Sway, project_points, turned_supine
from zedo_cli.evaluation.clips.eased import IMAGE_H, IMAGE_W, make_sequences
from zedo_cli.evaluation.clips.stillness import trunk_axes
from zedo_cli.lifting import clip
from zedo_cli.lifting.camera import Intrinsics
from zedo_cli.lifting.config import DEFAULT_SIGMA_FRAMES, get_preset
from zedo_cli.lifting.temporal import lift_sequence, smooth_on_frames, smooth_tracks_2d
from zedo_cli.prior.weights import load_prior, resolve_prior_path

SKELETON = get_skeleton("syrip12")
JOINTS = SKELETON.joints
FPS = 30.0
HELD = (("left_shoulder", "left_elbow"), ("left_elbow", "left_wrist"))
TORSO = [SKELETON.index(n) for n in clip.TORSO]


def held_arm_clip(poses: np.ndarray, seed: int, supine: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One 10 s clip: camera-frame truth `(T, 12, 3)`, 2D `(T, 12, 2)` and confidence `(T, 12)`."""
    rng = np.random.default_rng([seed, 7])
    seq = make_sequences(poses, rng, count=1, keyposes=11, transition_s=1.0, fps=FPS, noise_px=0.0, drop=0.03, gap=0,
                         interpolation="segments", sway=Sway() if supine else None)  # fmt: skip
    rel = seq["rel"].copy()
    axes, _ = trunk_axes(seq["rel"], JOINTS)
    for parent, child in HELD:
        a, c = JOINTS.index(parent), JOINTS.index(child)
        local = axes[0] @ (seq["rel"][0, c] - seq["rel"][0, a])
        rel[:, c] = rel[:, a] + np.einsum("tij,i->tj", axes, local)
    cam = rel + (seq["cam"] - seq["rel"])
    xy = project_points(cam, Intrinsics.pseudo(IMAGE_W, IMAGE_H)) + rng.normal(0.0, 3.0, seq["xy"].shape)
    xy[seq["conf"] == 0] = np.nan
    return cam, xy, seq["conf"]


def elbow_speeds(poses: np.ndarray) -> tuple[float, float]:
    """The left and right elbows' `3d_median_vel_angle` (deg/s) of camera-frame or root-relative poses."""
    rel = poses - poses[:, SKELETON.root_indices].mean(1, keepdims=True)
    values = features_3d(rel, SKELETON, FPS).values
    return values["3d_median_vel_angle_LElbow"], values["3d_median_vel_angle_RElbow"]


# A side rule: (unary costs (T, 2), separations (T,), near and far solutions (T, 3) each, the parent joint (T, 3),
# the bone (parent, child)) -> each frame's side (T,), 0 near and 1 far
SideRule = Callable[[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, tuple[str, str]], np.ndarray]


@contextmanager
def side_rule(rule: SideRule) -> Iterator[None]:
    """`clip.solve_limbs` choosing each bone's side by `rule`; it solves `clip.LIMB_BONES` in order, one
    `ray_solutions` and one `choose_sides` call a bone."""
    solutions, choose = clip.ray_solutions, clip.choose_sides
    bones = iter(clip.LIMB_BONES)
    last: dict[str, np.ndarray] = {}

    def recorded(parent: np.ndarray, ray: np.ndarray, length: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        near, far, reach = solutions(parent, ray, length)
        last.update(near=near, far=far, parent=parent)
        return near, far, reach

    def chosen(unary: np.ndarray, separation: np.ndarray) -> np.ndarray:
        return rule(unary, separation, last["near"], last["far"], last["parent"], next(bones))

    clip.ray_solutions, clip.choose_sides = recorded, chosen
    try:
        yield
    finally:
        clip.ray_solutions, clip.choose_sides = solutions, choose


def sides_kept_in_trunk_frame(torso: np.ndarray, cost: float) -> SideRule:
    """Clip mode's cost of changing side, plus `cost` per unit change of the bone's direction in the trunk frame of
    `torso (T, 4, 3)` between frames."""
    axes, _ = trunk_axes(torso, clip.TORSO)

    def rule(unary: np.ndarray, separation: np.ndarray, near: np.ndarray, far: np.ndarray, parent: np.ndarray,
             bone: tuple[str, str]) -> np.ndarray:  # fmt: skip
        length = np.linalg.norm(near - parent, axis=-1, keepdims=True)
        u = np.stack([np.einsum("tij,tj->ti", axes, (s - parent) / length) for s in (near, far)], 1)
        step = np.nan_to_num(np.linalg.norm(u[:-1, :, None] - u[1:, None, :], axis=-1))  # (T - 1, from, to)
        sep = np.nan_to_num(separation)
        pairwise = cost * step
        pairwise[:, 0, 1] += clip.SIDE_CHANGE_COST * np.minimum(sep[:-1], sep[1:])
        pairwise[:, 1, 0] += clip.SIDE_CHANGE_COST * np.minimum(sep[:-1], sep[1:])
        known = np.isfinite(unary).all(1)
        pairwise[~(known[:-1] & known[1:])] = 0.0
        return clip.best_path(np.nan_to_num(unary), pairwise)

    return rule


def true_sides(truth: np.ndarray) -> SideRule:
    """Each joint on the solution nearer its true place `truth (T, 12, 3)`."""

    def rule(unary: np.ndarray, separation: np.ndarray, near: np.ndarray, far: np.ndarray, parent: np.ndarray,
             bone: tuple[str, str]) -> np.ndarray:  # fmt: skip
        child = truth[:, SKELETON.index(bone[1])]
        return (np.linalg.norm(far - child, axis=-1) < np.linalg.norm(near - child, axis=-1)).astype(np.int8)

    return rule


def limbs(track: clip.ClipTrack, skel: clip.TrackSkeleton, torso: np.ndarray) -> np.ndarray:
    poses = clip.solve_limbs(track, skel, torso, SKELETON).poses.copy()
    poses[~np.isfinite(track.cam).all((1, 2))] = np.nan
    return poses


def variants(cam: np.ndarray, xy: np.ndarray, conf: np.ndarray, prior, cost: float) -> dict[str, tuple[float, float]]:  # noqa: ANN001
    """Per lift and oracle the held and moving elbows' speeds."""
    k = np.repeat(Intrinsics.pseudo(IMAGE_W, IMAGE_H).matrix()[None], len(xy), 0)
    out = {"truth": elbow_speeds(cam)}
    for mode in ("smooth", "two-pass", "clip"):
        res = lift_sequence(xy, conf, k, prior, get_preset("fast"), mode=mode, fps=FPS, seed=0)
        out[mode] = elbow_speeds(res.poses_root_relative)
        if mode == "two-pass":
            two_pass = res
    observed = two_pass.observed
    xy_smooth = smooth_tracks_2d(np.where(observed[..., None], xy, np.nan), DEFAULT_SIGMA_FRAMES)
    track = clip.ClipTrack(two_pass.poses_camera, observed, xy_smooth, k, FPS)
    skel = clip.estimate_skeleton(track, SKELETON, 0)
    lengths = {clip.BONE_NAMES[(a, c)]: float(np.median(np.linalg.norm(cam[:, SKELETON.index(a)]
                                                                       - cam[:, SKELETON.index(c)], axis=-1)))
               for a, c in clip.LIMB_BONES}  # fmt: skip
    true_skel = replace(skel, bones_m=lengths)
    lifted = np.isfinite(two_pass.poses_camera).all((1, 2))
    shape = clip.torso_shape(two_pass.poses_camera[lifted][:, TORSO])
    smooth: Callable[[np.ndarray], np.ndarray] = lambda v: smooth_on_frames(v, None, DEFAULT_SIGMA_FRAMES)  # noqa: E731
    torso = smooth(clip.place_torso(track, shape, SKELETON, skel.torso_m["trunk_length"]))
    true_torso = cam[:, TORSO]
    out["clip limbs"] = elbow_speeds(limbs(track, skel, torso))
    out["true torso and lengths"] = elbow_speeds(limbs(track, true_skel, true_torso))
    with side_rule(sides_kept_in_trunk_frame(true_torso, cost)):
        out["true torso and lengths + sides kept in the trunk frame"] = elbow_speeds(limbs(track, true_skel,
                                                                                            true_torso))  # fmt: skip
    with side_rule(sides_kept_in_trunk_frame(torso, cost)):
        out["estimated torso + sides kept in the trunk frame"] = elbow_speeds(limbs(track, skel, torso))
    with side_rule(true_sides(cam)):
        out["true torso and lengths, true sides"] = elbow_speeds(limbs(track, true_skel, true_torso))
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--syrip-dir", required=True)
    ap.add_argument("--clips", type=int, default=8)
    ap.add_argument("--supine", action="store_true", help="poses turned chest to the camera, the body swaying")
    ap.add_argument("--continuity", type=float, default=200.0, help="cost per unit change of direction (trunk frame)")
    args = ap.parse_args()
    poses = eased_source_poses(args.syrip_dir, "syrip-train")
    if args.supine:
        poses = turned_supine(poses, JOINTS)
    prior = load_prior(resolve_prior_path(None))
    rows: dict[str, list[tuple[float, float]]] = {}
    for i in range(args.clips):
        for name, speeds in variants(*held_arm_clip(poses, i, args.supine), prior, args.continuity).items():
            rows.setdefault(name, []).append(speeds)
    placed = "turned supine and swaying" if args.supine else "in their photos' orientation"
    print(f"{args.clips} clips of a held left arm, poses {placed}")
    print("| poses | held elbow deg/s | moving elbow deg/s |\n| --- | --- | --- |")
    for name, speeds in rows.items():
        held, moving = np.median(np.array(speeds), axis=0)
        print(f"| {name} | {held:.1f} | {moving:.1f} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
