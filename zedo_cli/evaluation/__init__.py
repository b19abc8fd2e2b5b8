"""Evaluation: MPJPE / PA-MPJPE, scoring a result file against ground truth, and the paper's
benchmarks (SyRIP Test100 with throughput, MINI-RGBD's two protocols).

Builds on every layer below the CLI except `augment`.
"""

from __future__ import annotations

from ..lazy import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(
    __name__,
    globals(),
    {
        ".metrics": ["mpjpe_mm", "pa_mpjpe_mm", "pa_per_joint_error_mm", "per_joint_error_mm"],
        ".minirgbd_benchmark": ["run_minirgbd_benchmark"],
        ".result_scoring": ["align_to_truth", "read_result_file"],
        ".syrip_benchmark": ["PAPER_FIGURES", "run_syrip_benchmark", "score_poses"],
    },
)
