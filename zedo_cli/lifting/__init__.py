"""Lifting 2D to 3D: the optimisation that keeps joints on their camera rays while the prior
denoises the pose (`solver`; its settings and presets in `config`), camera intrinsics and ray
geometry, choosing the people of a frame, and the temporal (video) mode.

Builds on `prior` and `data`; reads and writes no files except an intrinsics file.
"""

from __future__ import annotations

from ..lazy import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(
    __name__,
    globals(),
    {
        ".camera": [
            "Intrinsics",
            "PSEUDO_FOCAL_PX",
            "ResolvedCameras",
            "project",
            "resolve_cameras",
            "resolve_intrinsics",
        ],
        ".people": ["PERSON_MODES", "select_people"],
        ".config": ["DEFAULT_PRESET", "LiftConfig", "PRESETS", "TEMPORAL_MODES", "get_preset"],
        ".result": ["LiftResult"],
        ".solver": ["LiftProgress", "lift"],
        ".temporal": ["lift_sequence"],
    },
)
