"""The settings of the commands as typed models (pydantic): one per command, one field per long
option, with its type, bounds, default and help. The command line, `--config` TOML files (and
zedo results, as a `zedo lift` config) and the Python API (`zedo_cli.lift_file`,
`zedo_cli.analyze`) build the same models.

Builds on `lifting` (presets), `formats` (format names), `analysis` and `camera` (their defaults);
each command's model is its own module, so `zedo lift` does not import the analysis package.
"""

from __future__ import annotations

from ..lazy import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(
    __name__,
    globals(),
    {
        ".model": ["Options", "option_name"],
        ".lift": ["LiftOptions"],
        ".analyze": ["AnalyzeOptions"],
        ".render": ["RenderOptions"],
        ".calibrate": ["CalibrateOptions"],
        ".config_file": ["ConfigFile", "config_toml"],
        ".config": ["read_config"],
        ".device": ["check_device"],
    },
)
