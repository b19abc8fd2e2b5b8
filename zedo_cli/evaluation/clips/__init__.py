"""Synthetic infant clips of real movement: adult motion capture (../shared/data/adult) retargeted
to SyRIP training infants' bone lengths, laid supine under cameras clinics use, projected, and
given a 2D detector's habits with masks of where each went (docs/movement.md, "Clips of real
movement")."""

from __future__ import annotations

from ...lazy import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(
    __name__,
    globals(),
    {
        ".cameras": ["CLINIC_CAMERAS", "PSEUDO_CAMERA", "CameraSetup", "Sway"],
        ".eased": ["make_sequences", "segment_interpolation"],
        ".habits": ["DetectorHabits", "HabitMasks", "apply_habits"],
        ".infants": ["InfantBodies", "infant_bodies_from_poses", "infant_bodies_from_syrip"],
        ".motion": ["SEGMENTS", "AdultClip", "build_poses", "load_adult_clips", "resample", "segment_vectors"],
        ".source": [
            "AdultLibrary", "ClipSettings", "InfantClip", "adult_infant_clips", "load_adult_library",
            "retargeted_clips",
        ],
    },
)  # fmt: skip
