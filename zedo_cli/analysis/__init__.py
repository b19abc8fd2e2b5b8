"""Clinical measures of lifted poses (`zedo analyze`): postural symmetry (Huang et al. 2022),
joint angles in a trunk frame, movement features of sequences, measure-level estimates with
calibrated intervals (`analysis.calibration`), a clip's share of frames asymmetric with its
interval (`analysis.clip_share`), the tidy CSV / JSON outputs and the HTML report
(`analysis.report`, not imported here so that matplotlib loads only when a report is asked for).

Builds on `formats` (reading zedo results), `data` (joint sets by name) and `files`.
"""

from __future__ import annotations

from ..lazy import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(
    __name__,
    globals(),
    {
        ".analyse": ["Analysis", "AnalysisSettings", "COLUMNS", "Row", "all_measures", "analyse", "summary"],
        ".joint_angles": ["ANGLE_NAMES", "joint_angles", "trunk_frame"],
        ".outputs": ["analysis_document", "write_csv", "write_json"],
        ".symmetry": [
            "DEFAULT_THRESHOLD_DEG",
            "PAIRS",
            "measure_name",
            "symmetry_angles",
            "symmetry_band",
            "symmetry_call",
        ],
        ".calibration": [
            "CameraDomain",
            "MeasureCalibration",
            "MeasureModel",
            "assign_calibrations",
            "bundled_calibrations",
            "find_calibration",
        ],
        ".clip_share": ["Share", "probability_above", "share_interval"],
    },
)
