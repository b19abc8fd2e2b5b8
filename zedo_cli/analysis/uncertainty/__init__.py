"""The statistics behind the analysis's intervals, which know no measure: the measure-level calibration
(`calibration`), a clip's share of frames asymmetric with its interval (`clip_share`), the circular block
bootstrap over correlated frames (`block_bootstrap`) and its calibration for the head's clip measures
(`head_calibration`).

The lowest of the analysis's subpackages: imports nothing else of `analysis` (docs/ARCHITECTURE.md).
"""
