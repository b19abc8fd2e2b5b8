"""Names of the clip features of Chambers et al. 2020 as their code builds them, and which of zedo's
clip features the comparisons with typical infants use (analysis.norms)."""

from __future__ import annotations

import re

# The 38 pre-registered part-level features (left and right averaged), in the published order
# (compute_surprise.py's feature_list).
PUBLISHED_PART_FEATURES: tuple[str, ...] = (
    "Ankle_medianx", "Wrist_medianx", "Ankle_mediany", "Wrist_mediany",
    "Knee_mean_angle", "Elbow_mean_angle",
    "Ankle_IQRx", "Wrist_IQRx", "Ankle_IQRy", "Wrist_IQRy",
    "Knee_stdev_angle", "Elbow_stdev_angle",
    "Ankle_medianvelx", "Wrist_medianvelx", "Ankle_medianvely", "Wrist_medianvely",
    "Knee_median_vel_angle", "Elbow_median_vel_angle",
    "Ankle_IQRvelx", "Wrist_IQRvelx", "Ankle_IQRvely", "Wrist_IQRvely",
    "Knee_IQR_vel_angle", "Elbow_IQR_vel_angle",
    "Ankle_IQRaccx", "Wrist_IQRaccx", "Ankle_IQRaccy", "Wrist_IQRaccy",
    "Knee_IQR_acc_angle", "Elbow_IQR_acc_angle",
    "Ankle_meanent", "Wrist_meanent", "Knee_entropy_angle", "Elbow_entropy_angle",
    "Ankle_lrCorr_x", "Wrist_lrCorr_x", "Knee_lrCorr_angle", "Elbow_lrCorr_angle",
)  # fmt: skip

# Per-side features whose values are positive (speeds, spreads): log(left / right) is an asymmetry index.
ASYMMETRY_BASES: dict[str, tuple[str, ...]] = {
    **dict.fromkeys(("median_vel_angle", "IQR_vel_angle", "IQR_acc_angle"), ("Elbow", "Knee")),
    **dict.fromkeys(("medianvelx", "medianvely", "IQRvelx", "IQRvely", "IQRaccx", "IQRaccy", "IQRx", "IQRy"),
                    ("Wrist", "Ankle")),
    **dict.fromkeys(("3d_median_vel_angle", "3d_IQR_vel_angle", "3d_IQR_acc_angle"), ("Elbow", "Knee")),
}  # fmt: skip

_PER_SIDE = re.compile(r"^[A-Za-z_]+_[LR](Ankle|Wrist|Knee|Elbow|Hip|Shoulder)$")


def is_extended_feature(name: str) -> bool:
    """A feature of the extended comparison: a published per-side feature (`medianx_LAnkle`), a left-right
    correlation (`lrCorr_angle_Knee`), or one of zedo's 3D features (`3d_...`)."""
    return name.startswith("3d_") or name.startswith("lrCorr_") or bool(_PER_SIDE.match(name))
