"""zedo: lift 2D infant body keypoints to 3D with a diffusion pose prior (ZeDO-i).

The Python API, importable from here without knowing the tree; one file lifted and analysed,
with the settings of `zedo lift` and `zedo analyze` by their option names::

    import zedo_cli
    lifted = zedo_cli.lift_file("examples/prior_samples_coco.json", steps=30)
    table = zedo_cli.analyze(lifted).to_pandas()

and the steps underneath: read_keypoints, load_prior, resolve_intrinsics, lift, write_result.

Names load on first use (PEP 562), so `import zedo_cli` stays light: torch is imported only
when a lifting or prior name is first touched. The layout: docs/ARCHITECTURE.md.
"""

from __future__ import annotations

from .lazy import lazy_exports
from .version import __version__

__getattr__, __dir__, _names = lazy_exports(
    __name__,
    globals(),
    {
        ".data": ["Keypoints2D", "Skeleton", "get_skeleton", "load_npz_poses", "load_syrip_3d"],
        ".prior": ["Prior", "adapt_prior", "fit_prior", "load_prior", "resolve_prior_path"],
        ".lifting": ["Intrinsics", "LiftConfig", "LiftResult", "PRESETS", "get_preset", "lift", "lift_sequence",
                     "resolve_cameras", "resolve_intrinsics", "select_people"],
        ".camera": ["CameraModel", "read_camera_file"],
        ".formats": ["INPUT_FORMATS", "OUTPUT_FORMATS", "read_keypoints", "write_result"],
        ".augment": ["convert_poses", "load_augmenter"],
        ".pipeline.lift": ["LiftedInput", "lift_file"],
        ".pipeline.analyze_result": ["analyze"],
        ".settings": ["AnalyzeOptions", "LiftOptions"],
        ".evaluation": ["mpjpe_mm", "pa_mpjpe_mm", "run_syrip_benchmark"],
    },
)  # fmt: skip
__all__ = ["__version__", *_names]
