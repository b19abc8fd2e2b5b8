"""Augmentation: the domain-conditioned score network, its training (`augmenter`) and the
conversion of adult poses into infant-like ones (`conversion`); the figures are in
`augment.plots` (not imported here: matplotlib loads only when a figure is asked for).

Builds on `prior`, `data` and the output helpers of `formats`.
"""

from __future__ import annotations

from ..lazy import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(
    __name__,
    globals(),
    {
        ".augmenter": ["Augmenter", "load_augmenter", "save_augmenter", "train_augmenter"],
        ".conversion": ["choose_sources", "convert_poses", "take_bone_lengths"],
    },
)
