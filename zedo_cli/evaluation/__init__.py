"""Evaluation: MPJPE / PA-MPJPE, scoring a result file against ground truth, and the paper's
benchmarks (SyRIP Test100 with throughput, MINI-RGBD's two protocols).

Builds on every layer below the CLI except `augment`.
"""

from __future__ import annotations

from .metrics import mpjpe_mm, pa_mpjpe_mm, pa_per_joint_error_mm, per_joint_error_mm
from .minirgbd_benchmark import run_minirgbd_benchmark
from .result_scoring import align_to_truth, read_result_file
from .syrip_benchmark import PAPER_FIGURES, run_syrip_benchmark, score_poses

__all__ = [
    "PAPER_FIGURES", "align_to_truth", "mpjpe_mm", "pa_mpjpe_mm", "pa_per_joint_error_mm", "per_joint_error_mm",
    "read_result_file", "run_minirgbd_benchmark", "run_syrip_benchmark", "score_poses",
]  # fmt: skip
