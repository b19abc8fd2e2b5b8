"""Adult-to-infant pose conversion (`zedo augment`): size normalisation, the domain-conditioned
training set, the SDEdit-style conversion and orientation matching.

Scale. An infant is about a third of an adult's size, and a partly noised adult pose cannot
shrink that much and keep its posture. So the network works on size-normalised poses: every
pose (adult and infant, in training and in conversion) is scaled so that its skeleton size (the
sum of its bone lengths) equals `canonical` (the median adult size of the training data). The
tokens therefore learn proportions and posture, not size. After conversion each pose is given a
size: "infant" draws one from a log-normal fitted to the infant training sizes (clipped to 2.5
standard deviations), "keep" restores the input's own size.

Orientation. Training turns every batch by uniformly random rotations, so a token carries no
orientation and a conversion keeps its input's. `orient_like` can then turn each converted pose
so its torso (hips and shoulders) best matches a randomly drawn infant pose's, for training sets
in the infant data's camera frame.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import asdict, dataclass

import numpy as np
import torch

from ..data.datasets import PoseSet
from ..data.skeleton import Skeleton, bone_lengths, center_on_root
from ..errors import ConfigError, DataError, plural
from ..prior.sampling import integrate_reverse_sde
from ..prior.schedules import SCALE_MODES
from ..prior.sde import SubVPSDE
from ..rotation import best_rotation
from .domain_model import DomainScoreNet, domain_index

SIZE_CLIP_SD = 2.5
TORSO_JOINTS = ("left_hip", "right_hip", "left_shoulder", "right_shoulder")
CHUNK = 4096  # poses per network call in conversion


@dataclass(frozen=True)
class SizeModel:
    """Skeleton sizes (sums of bone lengths, metres): the canonical size the network works at,
    and the log-normal of the infant training sizes."""

    canonical: float
    infant_log_mean: float
    infant_log_std: float

    def to_dict(self) -> dict[str, float]:
        return asdict(self)

    def draw_infant_sizes(self, count: int, rng: np.random.Generator) -> np.ndarray:
        z = np.clip(rng.standard_normal(count), -SIZE_CLIP_SD, SIZE_CLIP_SD)
        return np.exp(self.infant_log_mean + self.infant_log_std * z)


def skeleton_size(poses: np.ndarray, skeleton: Skeleton) -> np.ndarray:
    """Sum of bone lengths `(N,)` of `poses (N, J, 3)`: a body size that does not depend on posture."""
    return bone_lengths(poses, skeleton).sum(-1)


def resize(poses: np.ndarray, skeleton: Skeleton, sizes: np.ndarray | float) -> np.ndarray:
    """`poses` scaled about the origin (their root) so each one's skeleton size is `sizes`."""
    current = skeleton_size(poses, skeleton)
    if not (current > 0).all():
        raise DataError(f"{plural(int((current <= 0).sum()), 'pose')} with all joints at one point (skeleton size 0)")
    return poses * (np.asarray(sizes, dtype=np.float64) / current)[:, None, None]


def fit_size_model(adult: PoseSet, infant: PoseSet) -> SizeModel:
    adult_sizes = skeleton_size(adult.poses, adult.skeleton)
    infant_log = np.log(skeleton_size(infant.poses, infant.skeleton))
    return SizeModel(float(np.median(adult_sizes)), float(infant_log.mean()), float(infant_log.std()))


def domain_training_set(adult: PoseSet, infant: PoseSet, sizes: SizeModel) -> tuple[torch.Tensor, torch.Tensor]:
    """Size-normalised poses `(M, J, 3)` and their domain labels `(M,)` (0 adult, 1 infant).

    The infant poses are repeated to about as many as the adult ones, so that every batch holds
    both domains in equal measure and the infant token is trained as often as the adult one.
    """
    if adult.skeleton.name != infant.skeleton.name:
        raise DataError(
            f"adult poses are in the {adult.skeleton.name} joint set, infant poses in {infant.skeleton.name}; "
            "the augmenter needs one joint set"
        )
    repeats = max(1, round(len(adult.poses) / len(infant.poses)))
    adult_c = resize(adult.poses, adult.skeleton, sizes.canonical)
    infant_c = np.tile(resize(infant.poses, infant.skeleton, sizes.canonical), (repeats, 1, 1))
    poses = torch.as_tensor(np.concatenate([adult_c, infant_c]), dtype=torch.float32)
    labels = torch.cat([
        torch.full((len(adult_c),), domain_index("adult")), torch.full((len(infant_c),), domain_index("infant"))
    ])  # fmt: skip
    return poses, labels


def check_strength(strength: float) -> None:
    if isinstance(strength, bool) or not isinstance(strength, (int, float)) or not 0 <= strength <= 1:
        raise ConfigError(f"--strength must be a noise level in [0, 1] (0 returns the input), got {strength!r}")


@torch.no_grad()
def convert_poses(
    model: DomainScoreNet,
    sde: SubVPSDE,
    sizes: SizeModel,
    skeleton: Skeleton,
    poses: np.ndarray,
    *,
    strength: float,
    steps: int = 100,
    domain: str = "infant",
    scale: str = "infant",
    seed: int = 0,
    on_step: Callable[[int, int], None] | None = None,
) -> np.ndarray:
    """Convert root-relative poses `(N, J, 3)` (metres) towards `domain`, SDEdit-style.

    Each pose is normalised to the canonical size, noised to time t0 = `strength` of the
    forward SDE, then denoised by `steps` reverse Euler-Maruyama steps from t0 to t0 / 1000
    conditioned on `domain`'s token, and finally sized by `scale` (module docstring). Strength 0
    skips the diffusion (with scale "keep" the output is the input). Seeded by `seed`.
    `on_step(done, total)` reports progress over all reverse steps of all chunks.
    """
    check_strength(strength)
    if isinstance(steps, bool) or not isinstance(steps, int) or steps < 1:
        raise ConfigError(f"--steps must be a positive integer, got {steps!r}")
    if scale not in SCALE_MODES:
        raise ConfigError(f"--scale must be one of {', '.join(SCALE_MODES)}, got {scale!r}")
    if poses.ndim != 3 or poses.shape[1:] != (skeleton.num_joints, 3):
        raise DataError(f"poses must have shape (N, {skeleton.num_joints}, 3), got {poses.shape}")
    label = domain_index(domain)
    rng = np.random.default_rng(seed)
    gen = torch.Generator().manual_seed(seed)
    in_sizes = skeleton_size(poses, skeleton)
    out = resize(poses, skeleton, sizes.canonical)
    if strength > 0:
        model.eval()
        chunks = []
        starts = range(0, len(out), CHUNK)
        done = 0

        def count_step() -> None:
            nonlocal done
            done += 1
            if on_step is not None:
                on_step(done, len(starts) * steps)

        for lo in starts:
            x0 = torch.as_tensor(out[lo : lo + CHUNK], dtype=torch.float32)
            t0 = torch.full((len(x0),), float(strength))
            xt = sde.perturb(x0, t0, torch.randn(x0.shape, generator=gen))
            x = integrate_reverse_sde(
                lambda x, t: model(x, t, label), sde, xt, t_start=float(strength), t_end=float(strength) * 1e-3,
                steps=steps, generator=gen, on_step=count_step,
            )  # fmt: skip
            chunks.append(x.double().numpy())
        out = center_on_root(np.concatenate(chunks), skeleton)  # the network does not pin the root
    targets = in_sizes if scale == "keep" else sizes.draw_infant_sizes(len(out), rng)
    return resize(out, skeleton, targets)


def torso_indices(skeleton: Skeleton, purpose: str) -> list[int]:
    """Indices of the hips and shoulders; a clear error naming `purpose` when the joint set lacks them."""
    missing = [j for j in TORSO_JOINTS if j not in skeleton.joints]
    if missing:
        raise ConfigError(f"{purpose} needs the torso joints; {skeleton.name} lacks {', '.join(missing)}")
    return [skeleton.index(j) for j in TORSO_JOINTS]


def orient_like(poses: np.ndarray, references: np.ndarray, skeleton: Skeleton, seed: int = 0) -> np.ndarray:
    """Each of `poses (N, J, 3)` turned about its root so its torso (hips, shoulders) best matches
    the torso of a reference pose drawn at random (seeded) from `references (M, J, 3)`."""
    torso = torso_indices(skeleton, "orienting")
    picks = np.random.default_rng(seed).integers(0, len(references), size=len(poses))
    rot = best_rotation(poses[:, torso], references[picks][:, torso])
    return poses @ rot


def limb_parents(skeleton: Skeleton) -> list[tuple[int, int]]:
    """(parent, child) joint pairs that grow the limbs out of the torso (hips and shoulders),
    breadth first, so each parent is placed before its children."""
    torso = torso_indices(skeleton, "growing limbs from the torso")
    placed, pairs, frontier = set(torso), [], list(torso)
    while frontier:
        nxt = []
        for parent in frontier:
            for a, b in skeleton.bones:
                child = b if a == parent else a if b == parent else None
                if child is not None and child not in placed:
                    placed.add(child)
                    pairs.append((parent, child))
                    nxt.append(child)
        frontier = nxt
    unreached = [skeleton.joints[j] for j in range(skeleton.num_joints) if j not in placed]
    if unreached:
        raise ConfigError(f"{skeleton.name}: joints not connected to the torso by bones: {', '.join(unreached)}")
    return pairs


def take_bone_lengths(poses: np.ndarray, references: np.ndarray, skeleton: Skeleton, seed: int = 0) -> np.ndarray:
    """Each of `poses (N, J, 3)` rebuilt with the bone proportions of a reference pose drawn at
    random (seeded) from `references (M, J, 3)`, keeping its own size, orientation and joint angles.

    The reference's torso, scaled to the pose's size, is turned onto the pose's torso (Kabsch);
    then every limb bone keeps the pose's direction and takes the reference's (scaled) length.
    """
    torso = torso_indices(skeleton, "taking bone lengths")
    pairs = limb_parents(skeleton)
    picks = np.random.default_rng(seed).integers(0, len(references), size=len(poses))
    ref = center_on_root(references[picks], skeleton)
    ref = ref * (skeleton_size(poses, skeleton) / skeleton_size(ref, skeleton))[:, None, None]
    rot = best_rotation(ref[:, torso], poses[:, torso])
    ref = ref @ rot
    out = np.array(poses, dtype=np.float64, copy=True)
    out[:, torso] = ref[:, torso]
    for parent, child in pairs:
        direction = poses[:, child] - poses[:, parent]
        norm = np.linalg.norm(direction, axis=-1, keepdims=True)
        length = np.linalg.norm(ref[:, child] - ref[:, parent], axis=-1, keepdims=True)
        out[:, child] = out[:, parent] + direction / np.maximum(norm, 1e-9) * length
    return center_on_root(out, skeleton)


def choose_sources(available: int, count: int, seed: int) -> np.ndarray:
    """Rows of `count` source poses drawn from `available` (seeded; without replacement when
    there are enough), in ascending order when drawn without replacement."""
    if isinstance(count, bool) or not isinstance(count, int) or count < 1:
        raise ConfigError(f"--count must be a positive number of poses, got {count!r}")
    rng = np.random.default_rng(seed)
    if count <= available:
        return np.sort(rng.choice(available, size=count, replace=False))
    return rng.integers(0, available, size=count)
