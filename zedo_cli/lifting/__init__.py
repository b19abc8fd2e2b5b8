"""Lifting 2D to 3D: the optimisation that keeps joints on their camera rays while the prior
denoises the pose (`solver`), camera intrinsics and ray geometry, choosing the people of a frame,
and the temporal (video) mode.

Builds on `prior` and `data`; reads and writes no files except an intrinsics file.
"""

from __future__ import annotations

from .camera import PSEUDO_FOCAL_PX, Intrinsics, project, resolve_intrinsics
from .people import PERSON_MODES, select_people
from .solver import DEFAULT_PRESET, PRESETS, LiftConfig, LiftProgress, LiftResult, get_preset, lift
from .temporal import TEMPORAL_MODES, lift_sequence

__all__ = [
    "DEFAULT_PRESET", "PERSON_MODES", "PRESETS", "PSEUDO_FOCAL_PX", "TEMPORAL_MODES", "Intrinsics", "LiftConfig",
    "LiftProgress", "LiftResult", "get_preset", "lift", "lift_sequence", "project", "resolve_intrinsics",
    "select_people",
]  # fmt: skip
