"""Clinical measures of lifted poses (`zedo analyze`): postural symmetry (Huang et al. 2022),
joint angles in a trunk frame, movement features of sequences, 90 % intervals from per-joint
uncertainty, the tidy CSV / JSON outputs and the HTML report (`analysis.report`, not imported
here so that matplotlib loads only when a report is asked for).

Builds on `formats` (reading zedo results), `data` (joint sets by name) and `files`.
"""

from __future__ import annotations

from .analyse import COLUMNS, Analysis, AnalysisSettings, Row, all_measures, analyse, summary
from .joint_angles import ANGLE_NAMES, joint_angles, trunk_frame
from .outputs import analysis_document, write_csv, write_json
from .symmetry import DEFAULT_THRESHOLD_DEG, PAIRS, measure_name, symmetry_angles, symmetry_band, symmetry_call
from .uncertainty import sample_intervals

__all__ = [
    "ANGLE_NAMES", "COLUMNS", "DEFAULT_THRESHOLD_DEG", "PAIRS", "Analysis", "AnalysisSettings", "Row",
    "all_measures", "analyse", "analysis_document", "joint_angles", "measure_name", "sample_intervals", "summary",
    "symmetry_angles", "symmetry_band", "symmetry_call", "trunk_frame", "write_csv", "write_json",
]  # fmt: skip
