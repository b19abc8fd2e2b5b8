"""Writing: a 3D result in every output format (JSON, JSON Lines, CSV, NPZ; TRC and C3D marker
files), one module per format; `outputs` is the entry point (format from the name, stdout,
checks). Nothing here imports the readers.
"""

from __future__ import annotations

from ...lazy import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(
    __name__,
    globals(),
    {
        ".outputs": [
            "FRAMES",
            "MARKER_FORMATS",
            "OUTPUT_FORMATS",
            "UNITS",
            "check_stdout",
            "default_output_name",
            "output_format",
            "write_result",
        ],
    },
)
