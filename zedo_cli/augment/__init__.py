"""Augmentation: the domain-conditioned score network, its training (`augmenter`) and the
conversion of adult poses into infant-like ones (`conversion`); the figures are in
`augment.plots` (not imported here: matplotlib loads only when a figure is asked for).

Builds on `prior`, `data` and the output helpers of `formats`.
"""

from __future__ import annotations

from .augmenter import Augmenter, load_augmenter, save_augmenter, train_augmenter
from .conversion import choose_sources, convert_poses, take_bone_lengths

__all__ = [
    "Augmenter", "choose_sources", "convert_poses", "load_augmenter", "save_augmenter", "take_bone_lengths",
    "train_augmenter",
]  # fmt: skip
