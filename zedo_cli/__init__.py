"""zedo: lift 2D infant body keypoints to 3D with a diffusion pose prior (ZeDO-i).

The Python API, importable from here without knowing the tree::

    from zedo_cli import read_keypoints, load_prior, resolve_intrinsics, lift, write_result

Names load on first use (PEP 562), so `import zedo_cli` stays light: torch is imported only
when a lifting or prior name is first touched. The layout: docs/ARCHITECTURE.md.
"""

from __future__ import annotations

import importlib
from typing import Any

from .version import __version__

# public name -> the subpackage that defines it
_API: dict[str, str] = {
    **dict.fromkeys(["Keypoints2D", "Skeleton", "get_skeleton", "load_syrip_3d", "load_npz_poses"], "data"),
    **dict.fromkeys(["Prior", "load_prior", "resolve_prior_path", "fit_prior", "adapt_prior"], "prior"),
    **dict.fromkeys(
        [
            "LiftConfig",
            "LiftResult",
            "PRESETS",
            "get_preset",
            "lift",
            "lift_sequence",
            "Intrinsics",
            "resolve_intrinsics",
            "select_people",
        ],
        "lifting",
    ),  # fmt: skip
    **dict.fromkeys(["read_keypoints", "write_result", "INPUT_FORMATS", "OUTPUT_FORMATS"], "formats"),
    **dict.fromkeys(["convert_poses", "load_augmenter"], "augment"),
    **dict.fromkeys(["mpjpe_mm", "pa_mpjpe_mm", "run_syrip_benchmark"], "evaluation"),
}

__all__ = ["__version__", *_API]


def __getattr__(name: str) -> Any:
    if name not in _API:
        raise AttributeError(f"module 'zedo_cli' has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{_API[name]}", __name__), name)
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_API))
