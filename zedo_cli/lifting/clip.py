"""`--temporal clip`: each person track of a video lifted as one infant, with one skeleton.

Frame-by-frame lifts give an infant bones that change length from frame to frame, and a limb that
points along the camera axis its depth side picked anew in every frame. Clip mode starts from the
`two-pass` lift of the track and then:

1. **One skeleton per track** (`estimate_skeleton`): a bone is at least as long as its parent joint's
   distance from its child's ray, and as long where it lies in the image plane; each of the eight limb
   bones' length is the 90th percentile of that distance over the track's frames where both its joints
   are observed (the parent where the two-pass lift put it). Each bone's share of the eight bones' sum
   has a 90 % interval, its width split-conformal on synthetic clips (`RATIO_LOG_ERROR_90`); the
   lengths themselves are in the lift's scale, which a pseudo camera does not fix. The torso's shape
   (both hips and both shoulders) is the median of the track's torso poses, rigidly aligned.
2. **The torso** of each frame is that shape, placed by OpenCV's PnP on the torso's smoothed 2D
   (from the two-pass pose, so it keeps its side), then each torso joint moved towards its ray by at most
   `TORSO_FLEX` of the trunk length: the shoulder girdle may move, within that tolerance.
3. **The limbs**, each bone from its parent outward: the child joint on its ray at the bone's exact
   length has two solutions, one towards the camera and one away (they meet where the bone lies in
   the image plane). The side is chosen over the whole track at once (`choose_sides`, a Viterbi pass):
   each frame prefers the side nearer the two-pass pose and a knee or elbow within its hinge's range
   (`HINGES`), and changing side costs `SIDE_CHANGE_COST` times how far apart the two solutions are, so
   the side changes only where the limb passes near the image plane. A joint not observed keeps its
   two-pass direction from its parent at the bone's length.
4. **Ambiguity said, not hidden**: between two passages near the image plane a limb keeps one side;
   where the two-pass pose hardly prefers it over that stretch (mean margin under `AMBIGUOUS_MARGIN` of
   the two solutions' distance), its child joint is flagged depth-ambiguous in every frame of the stretch.
5. **Over time**: the torso joints' paths and each limb bone's direction are smoothed by the temporal
   filter, and the limbs rebuilt at their lengths.

The 2D is the detections smoothed as in `two-pass` (rays through raw pixels bring their noise back).
A track too short for a skeleton (under `MIN_TRACK_FRAMES` frames with the limbs seen) keeps its
two-pass poses, and its skeleton says why.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
import torch

from ..data.skeleton import Skeleton, root_point
from ..rotation import best_rotation
from .camera import pixel_rays

Smoother = Callable[[np.ndarray], np.ndarray]

# (parent, child) of each limb bone, by joint name; each chain from the torso outward
LIMB_BONES = (
    ("left_hip", "left_knee"), ("left_knee", "left_ankle"), ("right_hip", "right_knee"), ("right_knee", "right_ankle"),
    ("left_shoulder", "left_elbow"), ("left_elbow", "left_wrist"),
    ("right_shoulder", "right_elbow"), ("right_elbow", "right_wrist"),
)  # fmt: skip
TORSO = ("left_hip", "right_hip", "left_shoulder", "right_shoulder")
CLIP_JOINTS = tuple(dict.fromkeys((*TORSO, *(j for b in LIMB_BONES for j in b))))  # what clip mode needs
BONE_NAMES = {
    ("left_hip", "left_knee"): "left_thigh", ("left_knee", "left_ankle"): "left_shank",
    ("right_hip", "right_knee"): "right_thigh", ("right_knee", "right_ankle"): "right_shank",
    ("left_shoulder", "left_elbow"): "left_upper_arm", ("left_elbow", "left_wrist"): "left_forearm",
    ("right_shoulder", "right_elbow"): "right_upper_arm", ("right_elbow", "right_wrist"): "right_forearm",
}  # fmt: skip
MIN_TRACK_FRAMES = 15  # frames with both joints of every limb bone seen: fewer give no skeleton
REACH_QUANTILE = 0.9  # of a bone's frames whose child ray its length reaches
PNP_MAX_SHIFT = 0.25  # of the torso's distance: how far PnP may move the torso from its rigid fit to the two-pass one
TORSO_FLEX = 0.1  # of the trunk length: how far a torso joint may leave the track's torso shape
SIDE_CHANGE_COST = 4.0  # per bone length of distance between the two solutions where the side changes
AMBIGUOUS_MARGIN = 0.5  # of the solutions' distance: a stretch whose side the two-pass pose prefers by less is flagged
# Knees bend backwards only, elbows forwards only: a solution bending one past straight by more than its slack
# (the sine of the angle) costs HINGE_COST per unit of that sine. The slacks leave the SyRIP training poses' knees
# within range in 98-100 % of poses and their elbows (whose hinge turns with the upper arm) in 99 %.
HINGES = {("left_knee", "left_ankle"): "knee", ("right_knee", "right_ankle"): "knee",
          ("left_elbow", "left_wrist"): "elbow", ("right_elbow", "right_wrist"): "elbow"}  # fmt: skip
HINGE_SLACK = {"knee": 0.2, "elbow": 0.4}
HINGE_COST = 3.0
# An observed joint whose ray passes further than this many bone lengths from its parent cannot be where the
# detector put it (a wrist on an adult's hand): it is not used and is flagged
UNREACHABLE = 1.35
NEAR_PLANE = 0.5  # a bone whose two solutions lie under this many bone lengths apart is near the image plane
LEVEL = 0.9
# The 90 % split-conformal quantile of |log(estimated / true share)| of a bone's share of the eight limb bones'
# sum, pooled over both clip sources and both cameras (benchmarks/accuracy/clip_mode.py --save-ratios; each
# source left out in turn: docs/lifting.md, "Clip mode").
RATIO_LOG_ERROR_90 = 0.090


@dataclass(frozen=True)
class TrackSkeleton:
    """One track's skeleton in the lift's own scale (metres): limb bone lengths with their 90 % intervals,
    and the torso's widths and trunk length; `fallback` says why a track kept its two-pass poses."""

    track: int | str  # the track's label
    frames: int  # frames the lengths were measured on
    bones_m: dict[str, float] = field(default_factory=dict)
    torso_m: dict[str, float] = field(default_factory=dict)
    fallback: str | None = None

    def to_dict(self) -> dict[str, object]:
        """The skeleton as a result's params record it."""
        out: dict[str, object] = {"track": self.track, "frames": self.frames}
        if self.fallback is not None:
            out["fallback"] = self.fallback
            return out
        total = sum(self.bones_m.values())
        spread = np.exp(RATIO_LOG_ERROR_90)
        out["bones"] = {b: {"length_m": _r(v), "share": _r(v / total), "share_low": _r(v / total / spread),
                            "share_high": _r(v / total * spread)} for b, v in self.bones_m.items()}  # fmt: skip
        out["torso"] = {k: _r(v) for k, v in self.torso_m.items()}
        out["level"] = LEVEL
        out["method"] = (f"length: the {REACH_QUANTILE:.0%} quantile, over the track's frames with both joints seen, "
                         "of the parent joint's distance from the child's ray (the lift's scale); share: the bone "
                         "over the eight limb bones' sum, its interval split-conformal on synthetic clips of SyRIP "
                         "poses and of adult motion made infant-like")  # fmt: skip
        return out


def _r(x: float) -> float:
    return float(f"{x:.6g}")


def joint_indices(skeleton: Skeleton) -> dict[str, int]:
    """The index in `skeleton` of each joint clip mode uses (CLIP_JOINTS)."""
    return {n: skeleton.index(n) for n in CLIP_JOINTS}


def unit_rays(xy: np.ndarray, intrinsics: np.ndarray) -> np.ndarray:
    """Unit rays `(T, J, 3)` through pixels `(T, J, 2)` (undistorted) of cameras `(T, 3, 3)`; NaN where missing."""
    rays = pixel_rays(torch.as_tensor(xy, dtype=torch.float64), torch.as_tensor(intrinsics, dtype=torch.float64))
    rays = rays.numpy()
    return rays / np.linalg.norm(rays, axis=-1, keepdims=True)


def ray_solutions(parent: np.ndarray, ray: np.ndarray, length: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The two points `(T, 3)` on the rays `(T, 3)` at `length` from `parent (T, 3)` (nearer and further
    from the camera), and `reach (T,)`: False where the ray passes further than `length` from the parent
    (both are then the point at `length` towards the ray's closest approach)."""
    along = (ray * parent).sum(-1)  # depth of the closest approach
    disc = along**2 - (parent * parent).sum(-1) + length**2
    reach = disc >= 0
    half = np.sqrt(np.maximum(disc, 0.0))
    near, far = (along - half)[:, None] * ray, (along + half)[:, None] * ray
    closest = along[:, None] * ray - parent
    norm = np.linalg.norm(closest, axis=-1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        short = parent + length * closest / norm
    near = np.where(reach[:, None], near, short)
    far = np.where(reach[:, None], far, short)
    return near, far, reach


def best_path(unary: np.ndarray, pairwise: np.ndarray) -> np.ndarray:
    """The states `(T,)` (0 or 1) of least total cost over a chain (Viterbi): `unary (T, 2)` the cost of each state
    in each frame, `pairwise (T - 1, 2, 2)` of each step [from, to]; a tie keeps the state, and ends in state 0."""
    t = len(unary)
    total = unary[0].copy()
    back = np.zeros((t, 2), dtype=np.int8)
    for i in range(1, t):
        options = total[:, None] + pairwise[i - 1]  # (from, to)
        stay, switch = np.diagonal(options), np.array([options[1, 0], options[0, 1]])
        back[i] = np.where(stay <= switch, [0, 1], [1, 0])
        total = np.minimum(stay, switch) + unary[i]
    states = np.empty(t, dtype=np.int8)
    states[-1] = int(np.argmin(total))
    for i in range(t - 1, 0, -1):
        states[i - 1] = back[i, states[i]]
    return states


def choose_sides(cost: np.ndarray, separation: np.ndarray) -> np.ndarray:
    """Per frame the side `(T,)` (0 near, 1 far) of least total cost over the track: `cost (T, 2)` of each side in
    each frame (NaN: no preference), plus SIDE_CHANGE_COST x the solutions' `separation (T,)` (in bone lengths,
    the smaller of the two frames') at each change of side (`best_path`)."""
    sep = np.nan_to_num(separation, nan=0.0)
    change = SIDE_CHANGE_COST * np.minimum(sep[:-1], sep[1:])  # (T - 1,)
    pairwise = np.zeros((max(len(sep) - 1, 0), 2, 2))
    pairwise[:, 0, 1] = pairwise[:, 1, 0] = change
    return best_path(np.nan_to_num(cost, nan=0.0), pairwise)


def ambiguous_stretches(margin: np.ndarray, separation: np.ndarray) -> np.ndarray:
    """`(T,)` frames in stretches between passages near the image plane (`separation` under NEAR_PLANE) whose
    mean preference `margin (T,)` for the chosen side (in the two solutions' distance; NaN: none) is under
    AMBIGUOUS_MARGIN."""
    near = np.nan_to_num(separation, nan=0.0) < NEAR_PLANE
    stretch = np.cumsum(near)  # a new stretch after every near-plane frame
    known = np.isfinite(margin) & ~near
    counts = np.bincount(stretch[known], minlength=len(margin) + 1)
    sums = np.bincount(stretch[known], margin[known], minlength=len(margin) + 1)
    with np.errstate(invalid="ignore", divide="ignore"):
        weak = (counts > 0) & (sums / counts < AMBIGUOUS_MARGIN)  # per stretch
    return ~near & weak[stretch]


def _rigid_fit(source: np.ndarray, target: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rotation `(3, 3)` (column vectors: rot @ x) and translation `(3,)` taking the points `source (P, 3)` closest
    to `target (P, 3)`."""
    cs, ct = source.mean(0), target.mean(0)
    rot = best_rotation(source - cs, target - ct).T
    return rot, ct - rot @ cs


@dataclass(frozen=True)
class ClipTrack:
    """One track's arrays, frames in time order: the two-pass poses `cam (T, J, 3)` (camera frame, NaN where
    not lifted), `observed (T, J)`, smoothed undistorted pixels `xy (T, J, 2)`, `intrinsics (T, 3, 3)`."""

    cam: np.ndarray
    observed: np.ndarray
    xy: np.ndarray
    intrinsics: np.ndarray
    fps: float


def estimate_skeleton(track: ClipTrack, skeleton: Skeleton, label: int | str) -> TrackSkeleton:
    """The track's limb bone lengths (with 90 % intervals) and torso widths; a fallback where too few
    frames show every limb."""
    at = joint_indices(skeleton)
    lifted = np.isfinite(track.cam).all((1, 2))
    rays = unit_rays(track.xy, track.intrinsics)
    bones = {}
    counts = []
    for parent, child in LIMB_BONES:
        seen = lifted & track.observed[:, at[parent]] & track.observed[:, at[child]]
        counts.append(int(seen.sum()))
        if seen.sum() < MIN_TRACK_FRAMES:
            continue
        p, r = track.cam[seen, at[parent]], rays[seen, at[child]]
        gap = np.linalg.norm(p - (p * r).sum(-1, keepdims=True) * r, axis=-1)  # the parent's distance from the ray
        name = BONE_NAMES[(parent, child)]
        bones[name] = float(np.quantile(gap, REACH_QUANTILE))

    if len(bones) < len(LIMB_BONES):
        return TrackSkeleton(label, min(counts), fallback=(
            f"too few frames with every limb seen for a skeleton ({min(counts)}; {MIN_TRACK_FRAMES} needed): "
            "lifted as two-pass"))  # fmt: skip
    torso = track.cam[lifted][:, [at[n] for n in TORSO]]
    shape = torso_shape(torso)
    hips, shoulders = shape[:2].mean(0), shape[2:].mean(0)
    widths = {"hip_width": float(np.linalg.norm(shape[0] - shape[1])),
              "shoulder_width": float(np.linalg.norm(shape[2] - shape[3])),
              "trunk_length": float(np.linalg.norm(shoulders - hips))}  # fmt: skip
    return TrackSkeleton(label, min(counts), bones, widths)


def torso_shape(torso: np.ndarray) -> np.ndarray:
    """The median shape `(4, 3)` of torso poses `(T, 4, 3)` (hips, then shoulders), each rigidly aligned to the
    first, centred at the origin."""
    ref = torso[0] - torso[0].mean(0)
    aligned = []
    for pose in torso:
        rot, shift = _rigid_fit(pose, ref)
        aligned.append(pose @ rot.T + shift)
    shape = np.median(np.stack(aligned), axis=0)
    return shape - shape.mean(0)


def place_torso(track: ClipTrack, shape: np.ndarray, skeleton: Skeleton, trunk: float) -> np.ndarray:
    """Per frame the torso joints `(T, 4, 3)`: `shape` placed by PnP on the torso's pixels from its rigid fit to
    the two-pass torso, then each joint moved towards its ray by at most TORSO_FLEX x `trunk`."""
    import cv2

    idx = [skeleton.index(n) for n in TORSO]
    out = np.full((len(track.cam), 4, 3), np.nan)
    rays = unit_rays(track.xy[:, idx], track.intrinsics)
    for t in np.flatnonzero(np.isfinite(track.cam[:, idx]).all((1, 2))):
        rot, shift = _rigid_fit(shape, track.cam[t, idx])
        seen = track.observed[t, idx]
        if seen.all():
            rvec, _ = cv2.Rodrigues(rot)
            ok, rvec, tvec = cv2.solvePnP(shape, track.xy[t, idx].astype(np.float64), track.intrinsics[t], None,
                                          rvec, shift.reshape(3, 1).copy(), True, cv2.SOLVEPNP_ITERATIVE)  # fmt: skip
            # a PnP that moved the torso far from its rigid fit has found another minimum: kept out
            if ok and np.linalg.norm(tvec[:, 0] - shift) < PNP_MAX_SHIFT * np.linalg.norm(shift):
                rot, shift = cv2.Rodrigues(rvec)[0], tvec[:, 0]
        placed = shape @ rot.T + shift
        on_ray = (rays[t] * placed).sum(-1, keepdims=True) * rays[t]
        move = on_ray - placed
        dist = np.linalg.norm(move, axis=-1, keepdims=True)
        limit = TORSO_FLEX * trunk
        step = np.where(dist > limit, move * limit / np.maximum(dist, 1e-12), move)
        out[t] = np.where(seen[:, None], placed + step, placed)
    return out


def hyperextension(poses: np.ndarray, child: np.ndarray, middle: str, end: str, at: dict[str, int]) -> np.ndarray:
    """`(T,)` how far past straight the hinge at `middle` bends with its distal joint at `child (T, 3)`: the
    distal bone's component (unit bone) along the side a knee never bends to (the thigh's front) or an elbow
    (the upper arm's back), beyond its HINGE_SLACK; 0 within the joint's range."""
    side = HINGES[(middle, end)]
    prox = {"knee": "hip", "elbow": "shoulder"}[side]
    lr = "left" if middle.startswith("left") else "right"
    lateral = poses[:, at[f"left_{prox}"]] - poses[:, at[f"right_{prox}"]]  # towards the body's left
    upper = poses[:, at[middle]] - poses[:, at[f"{lr}_{prox}"]]
    front = np.cross(upper, lateral)  # the front of the thigh or upper arm, (left, up, forward) right-handed
    front /= np.linalg.norm(front, axis=-1, keepdims=True)
    distal = child - poses[:, at[middle]]
    along = (distal * front).sum(-1) / np.linalg.norm(distal, axis=-1)
    past = along if side == "knee" else -along
    return np.maximum(past - HINGE_SLACK[side], 0.0)


@dataclass(frozen=True)
class LimbSolution:
    """A track's limbs: poses `(T, J, 3)`, the joints flagged depth-ambiguous `(T, J)`, the observed joints whose
    ray passes too far from their parent for the bone `(T, J)` (`UNREACHABLE`: not used), and at an ankle or wrist
    the knee's or elbow's flexion with the other side's solution `(T, J)` (degrees, 0 = straight; NaN elsewhere)."""

    poses: np.ndarray
    ambiguous: np.ndarray
    unreachable: np.ndarray
    other_flexion_deg: np.ndarray


def flexion_deg(proximal: np.ndarray, middle: np.ndarray, distal: np.ndarray) -> np.ndarray:
    """`(T,)` the flexion at `middle` of the chain proximal-middle-distal `(T, 3)` each: 0 = straight."""
    u, v = proximal - middle, distal - middle
    with np.errstate(invalid="ignore", divide="ignore"):
        cos = (u * v).sum(-1) / np.linalg.norm(u, axis=-1) / np.linalg.norm(v, axis=-1)
    return 180.0 - np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


def solve_limbs(track: ClipTrack, skel: TrackSkeleton, torso: np.ndarray, skeleton: Skeleton) -> LimbSolution:
    """The track's limbs with the torso `(T, 4, 3)` and every limb bone at its length, the sides chosen over the
    track (`choose_sides`)."""
    at = joint_indices(skeleton)
    out = track.cam.copy()
    out[:, [at[n] for n in TORSO]] = torso
    ambiguous = np.zeros(track.observed.shape, bool)
    outliers = np.zeros(track.observed.shape, bool)
    other_flexion = np.full(track.observed.shape, np.nan)
    rays = unit_rays(track.xy, track.intrinsics)
    ok = np.isfinite(torso).all((1, 2))
    for parent, child in LIMB_BONES:
        length = skel.bones_m[BONE_NAMES[(parent, child)]]
        p_new, p_old, c_old = out[:, at[parent]], track.cam[:, at[parent]], track.cam[:, at[child]]
        direction = c_old - p_old
        with np.errstate(invalid="ignore", divide="ignore"):
            kept = p_new + length * direction / np.linalg.norm(direction, axis=-1, keepdims=True)
        ray = np.where(track.observed[:, at[child], None], rays[:, at[child]], 0.0)
        gap = np.linalg.norm(p_new - (ray * p_new).sum(-1, keepdims=True) * ray, axis=-1)
        with np.errstate(invalid="ignore"):
            unreachable = track.observed[:, at[child]] & ok & (gap > UNREACHABLE * length)
        outliers[:, at[child]] = unreachable
        seen = track.observed[:, at[child]] & ok & ~unreachable
        near, far, reach = ray_solutions(p_new, np.where(seen[:, None], rays[:, at[child]], 0.0), length)
        cost = np.stack([np.linalg.norm(near - kept, axis=-1), np.linalg.norm(far - kept, axis=-1)], 1) / length
        if (parent, child) in HINGES:
            cost += HINGE_COST * np.stack([hyperextension(out, near, parent, child, at),
                                           hyperextension(out, far, parent, child, at)], 1)  # fmt: skip
        separation = np.linalg.norm(far - near, axis=-1) / length
        cost[~(seen & reach)] = np.nan
        separation[~(seen & reach)] = 0.0
        sides = choose_sides(cost, separation)
        chosen = np.where((sides == 0)[:, None], near, far)
        out[:, at[child]] = np.where((seen & ok)[:, None], chosen, np.where(ok[:, None], kept, np.nan))
        gain = (
            np.take_along_axis(cost, (1 - sides)[:, None], 1)[:, 0] - np.take_along_axis(cost, sides[:, None], 1)[:, 0]
        )
        with np.errstate(invalid="ignore", divide="ignore"):
            margin = (
                gain / separation
            )  # 1: the two-pass pose on the chosen solution, 0: half-way, < 0: nearer the other
        ambiguous[:, at[child]] = ambiguous_stretches(margin, separation) & seen & reach
        if (parent, child) in HINGES:  # the knee's or elbow's flexion had the limb taken the other side
            proximal = parent.replace("knee", "hip").replace("elbow", "shoulder")
            other = np.where((sides == 0)[:, None], far, near)
            other_flexion[:, at[child]] = np.where(ambiguous[:, at[child]],
                                                   flexion_deg(out[:, at[proximal]], p_new, other), np.nan)  # fmt: skip
    return LimbSolution(out, ambiguous, outliers, other_flexion)


def smooth_chains(poses: np.ndarray, skel: TrackSkeleton, skeleton: Skeleton, smooth: Smoother) -> np.ndarray:
    """`poses (T, J, 3)` with the torso joints' paths and every limb bone's direction smoothed over time by
    `smooth`, the limbs rebuilt from the torso outward at their lengths (which smoothing positions would break)."""
    at = joint_indices(skeleton)
    out = poses.copy()
    torso = [at[n] for n in TORSO]
    out[:, torso] = smooth(poses[:, torso])
    for parent, child in LIMB_BONES:
        step = poses[:, at[child]] - poses[:, at[parent]]
        direction = smooth(step / np.linalg.norm(step, axis=-1, keepdims=True))
        direction /= np.linalg.norm(direction, axis=-1, keepdims=True)
        out[:, at[child]] = out[:, at[parent]] + skel.bones_m[BONE_NAMES[(parent, child)]] * direction
    return out


@dataclass(frozen=True)
class TrackLift:
    """One track lifted as one infant: poses `(T, J, 3)` in the camera frame, the joints flagged depth-ambiguous
    `(T, J)`, the observed joints not used as unreachable `(T, J)`, and the track's skeleton."""

    poses: np.ndarray
    ambiguous: np.ndarray
    unreachable: np.ndarray
    skeleton: TrackSkeleton
    other_flexion_deg: np.ndarray  # `LimbSolution.other_flexion_deg`


def lift_clip_track(track: ClipTrack, skeleton: Skeleton, label: int | str, smooth: Smoother) -> TrackLift:
    """One track lifted as one infant (the two-pass poses where its skeleton has a fallback). `smooth` filters a
    track's series `(T, ...)` over time (NaN-aware), as the temporal modes do."""
    skel = estimate_skeleton(track, skeleton, label)
    none = np.zeros(track.observed.shape, bool)
    if skel.fallback is not None:
        return TrackLift(track.cam.copy(), none, none, skel, np.full(track.observed.shape, np.nan))
    lifted = np.isfinite(track.cam).all((1, 2))
    shape = torso_shape(track.cam[lifted][:, [skeleton.index(n) for n in TORSO]])
    torso = place_torso(track, shape, skeleton, skel.torso_m["trunk_length"])
    limbs = solve_limbs(track, skel, torso, skeleton)
    poses = limbs.poses.copy()
    poses[~lifted] = np.nan
    poses = smooth_chains(poses, skel, skeleton, smooth)
    return TrackLift(poses, limbs.ambiguous & lifted[:, None], limbs.unreachable & lifted[:, None], skel,
                     np.where(lifted[:, None], limbs.other_flexion_deg, np.nan))  # fmt: skip


def root_relative(poses: np.ndarray, skeleton: Skeleton) -> tuple[np.ndarray, np.ndarray]:
    """Root-relative poses `(N, J, 3)` and root points `(N, 3)` of camera-frame poses `(N, J, 3)`."""
    root = root_point(poses, skeleton)
    return poses - root[:, None], root


def limb_parents(skeleton: Skeleton) -> list[int | None]:
    """Per joint of `skeleton` the index of its limb parent (`LIMB_BONES`), None for the torso's and others."""
    parent = {child: p for p, child in LIMB_BONES}
    return [
        skeleton.index(parent[j]) if j in parent and parent[j] in skeleton.joints else None for j in skeleton.joints
    ]


def needs_joints(skeleton: Skeleton) -> Sequence[str]:
    """The joints clip mode needs that `skeleton` lacks (empty: it has them all)."""
    return [n for n in CLIP_JOINTS if n not in skeleton.joints]
