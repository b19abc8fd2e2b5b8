"""The reference of typical infants (`zedo norms`): the per-feature fits and the surprise (`norms`) and the
reference file (`norms_file`). A clip's comparison with it, as rows of an analysis, is `analysis.compare`.

Imports from `analysis.uncertainty`, `analysis.pose` and `analysis.clip` only, within the analysis
(docs/ARCHITECTURE.md).
"""
