"""Infant segment lengths for retargeting adult motion: one SyRIP training pose's per clip.

Only SyRIP's 600 training poses are read (`load_syrip_3d(..., "train")`: 3D rows 0-299 and
1400-1699); Test100 (rows 1300-1399) and the synthetic rows 300-1299 are never touched.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...data.datasets import load_syrip_3d
from ...errors import DataError
from .motion import SEGMENTS, TWIN_SEGMENTS, segment_vectors


@dataclass(frozen=True)
class InfantBodies:
    """Segment lengths `(N, 13)` in metres (order of `motion.SEGMENTS`) of N infant poses, and each
    pose's name (a SyRIP image name)."""

    lengths: np.ndarray
    names: tuple[str, ...]
    source: str

    def __post_init__(self) -> None:
        if self.lengths.ndim != 2 or self.lengths.shape[1] != len(SEGMENTS) or len(self.names) != len(self.lengths):
            raise DataError(f"infant lengths must be (N, {len(SEGMENTS)}) with one name per pose")
        if len(self.names) == 0 or not (np.isfinite(self.lengths).all() and (self.lengths > 0).all()):
            raise DataError("infant lengths must be finite and positive, at least one pose")

    def draw(self, rng: np.random.Generator, symmetric: bool) -> tuple[np.ndarray, str]:
        """One pose's lengths `(13,)` and name, drawn uniformly; with `symmetric`, each limb's
        left and right lengths replaced by their mean (SyRIP's right thigh is shorter in 86 % of
        its poses, a bias of the data, not of infants)."""
        i = int(rng.integers(len(self.names)))
        lengths = self.lengths[i].copy()
        if symmetric:
            for a, b in TWIN_SEGMENTS:
                lengths[[a, b]] = lengths[[a, b]].mean()
        return lengths, self.names[i]


def infant_bodies_from_poses(poses: np.ndarray, names: list[str] | tuple[str, ...], source: str) -> InfantBodies:
    """The segment lengths of syrip12 poses `(N, 12, 3)` (any units' metres, any placement)."""
    return InfantBodies(np.linalg.norm(segment_vectors(np.asarray(poses, dtype=np.float64)), axis=-1),
                        tuple(names), source)  # fmt: skip


def infant_bodies_from_syrip(syrip_dir: str | Path) -> InfantBodies:
    """The 600 SyRIP training poses' segment lengths (never Test100 or the synthetic rows)."""
    train = load_syrip_3d(syrip_dir, "train")
    return infant_bodies_from_poses(train.poses, train.names, train.source)
