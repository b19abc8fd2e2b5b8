"""Clinical measures of lifted poses (`zedo analyze`), by measure family: the statistics of the
intervals (`uncertainty`: measure-level calibration, a clip's share of frames asymmetric, the block
bootstrap), measures of a pose or frame (`pose`: postural symmetry after Huang et al. 2022, joint
angles in a trunk frame, the head), features of a clip (`clip`: movement, the published 2D and the
`3d_` features), the reference of typical infants (`norms`), then the orchestration at this level
(`analyse`, `outputs`: the tidy CSV / JSON, `compare`: a clip against a reference) and the HTML
report (`report`, not imported here so that matplotlib loads only when a report is asked for).
Each imports only from its own folder and the ones listed before it (docs/ARCHITECTURE.md).

Builds on `formats` (reading zedo results), `data` (joint sets by name) and `files`.
"""

from __future__ import annotations

from ..lazy import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(
    __name__,
    globals(),
    {
        ".analyse": ["Analysis", "AnalysisSettings", "COLUMNS", "Row", "all_measures", "analyse", "summary"],
        ".pose.joint_angles": ["ANGLE_NAMES", "joint_angles", "trunk_frame"],
        ".outputs": ["analysis_document", "write_csv", "write_json"],
        ".pose.symmetry": [
            "DEFAULT_THRESHOLD_DEG",
            "PAIRS",
            "measure_name",
            "symmetry_angles",
            "symmetry_band",
            "symmetry_call",
        ],
        ".uncertainty.calibration": [
            "CameraDomain",
            "MeasureCalibration",
            "MeasureModel",
            "assign_calibrations",
            "bundled_calibrations",
            "find_calibration",
        ],
        ".uncertainty.clip_share": ["Share", "probability_above", "share_interval"],
    },
)
