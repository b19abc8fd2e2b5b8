"""What `zedo lift` and `zedo analyze` run for one input, as library functions, and the
two-line Python API over them: `lift_file(path, **settings)` and `analyze(result, **settings)`,
with the commands' settings by their option names (`settings.LiftOptions`, `AnalyzeOptions`).

Builds on `settings`, `formats`, `lifting`, `analysis` and `footage`; the CLI adds progress,
tables and exit codes.
"""

from __future__ import annotations

from ..lazy import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(
    __name__,
    globals(),
    {
        ".lift": ["LiftPlan", "LiftedInput", "lift_file", "plan_lift"],
        ".analyze_result": ["analyze"],
    },
)
