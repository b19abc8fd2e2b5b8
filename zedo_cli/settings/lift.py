"""`LiftOptions`: every option of `zedo lift`, for the command line, `--config` and `zedo_cli.lift_file`."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, ClassVar, Literal, Optional

from pydantic import Field, field_validator

from ..data.skeleton import SKELETONS, get_skeleton
from ..errors import ConfigError
from ..formats import INPUT_FORMATS, OUTPUT_FORMATS
from ..formats.writers.markers import MARKER_AXES
from ..formats.writers.outputs import FRAMES, UNITS
from ..lifting.config import DEFAULT_PRESET, DEFAULT_SIGMA_FRAMES, MAX_HYPOTHESES, PRESETS, TEMPORAL_MODES, LiftConfig
from ..lifting.people import PERSON_MODES
from .limits import DEVICE_HELP, MAX_FOCAL_PX, MAX_FPS, MAX_SEED, MAX_SIGMA_FRAMES, MAX_STEPS
from .model import Options, show

ENGINES = ("local", "ray")
_FAST = PRESETS["fast"]
# A path option: a string from a TOML file or the Python API is a path.
PathOption = Annotated[Optional[Path], Field(strict=False)]
Size = Annotated[float, Field(gt=0, le=MAX_FOCAL_PX)]

# What a lift's poses depend on, recorded in a result's params.options (so that the result can be
# a --config that lifts again: settings.from_result); the rest says where outputs go and how to run.
RERUN_KEYS = (
    "format", "skeleton", "person", "min_confidence", "image_size", "images", "video", "fps", "focal",
    "principal_point", "intrinsics", "camera", "prior", "preset", "steps", "temporal", "sigma", "hypotheses", "seed",
    "calibration", "ray_weight", "ray_confidence_ratio", "hip_ray_factor", "twin_rate", "proportion_rate",
    "twin_ratio_cap", "units", "frame", "marker_axes", "save_hypotheses", "device",
)  # fmt: skip
# The LiftConfig numbers an option sets (None: the preset's).
CONFIG_KEYS = ("steps", "hypotheses", "ray_weight", "ray_confidence_ratio", "hip_ray_factor", "twin_rate",
               "proportion_rate", "twin_ratio_cap")  # fmt: skip


class LiftOptions(Options):
    """The settings of `zedo lift` (and of `zedo_cli.lift_file`), one field per long option."""

    command: ClassVar[str] = "lift"

    # Input
    format: Literal[INPUT_FORMATS] = Field("auto", description="Input layout, when detection is not wanted.")  # type: ignore[valid-type]
    skeleton: Optional[str] = Field(
        None,
        description=f"Joint set of an input without joint names: {', '.join(SKELETONS)}.",
        json_schema_extra={"expected": f"one of {', '.join(SKELETONS)}"},
    )
    person: Literal[PERSON_MODES] = Field(  # type: ignore[valid-type]
        "auto",
        description=f"Whom to lift in a frame of several people: {', '.join(PERSON_MODES)} (auto: the most "
        "complete, then the same person frame after frame).",
    )
    min_confidence: float = Field(
        0.0, ge=0, le=1, description="Joints below this confidence are missing (the prior fills them)."
    )
    image_size: Optional[tuple[Size, Size]] = Field(
        None,
        description="Image size in pixels, for inputs without one (COCO results, OpenPose).",
        json_schema_extra={"expected": "two numbers, WIDTH HEIGHT, each > 0"},
    )
    images: PathOption = Field(None, description="COCO annotations giving a COCO results input its image sizes.")
    video: PathOption = Field(
        None,
        description="The video the keypoints came from: its image size and fps; keypoint frames beyond it are an "
        "error (docs/footage.md).",
    )
    fps: Optional[float] = Field(
        None, gt=0, le=MAX_FPS, description="Frame rate of a video input, recorded in the output. Default: --video's."
    )
    # Camera
    focal: Optional[float] = Field(
        None, gt=0, le=MAX_FOCAL_PX, description="Focal length in pixels. Default: the paper's pseudo 2000 px."
    )
    principal_point: Optional[tuple[float, float]] = Field(
        None, description="Principal point in pixels. Default: the image centre."
    )
    intrinsics: PathOption = Field(
        None,
        description="Calibration file, lens distortion included: zedo JSON, OpenCV FileStorage (YAML, XML, JSON), "
        "Pose2Sim / anipose TOML (docs/cameras.md).",
    )
    camera: Optional[str] = Field(None, description="The camera, by name, of an --intrinsics file holding several.")
    # Lifting
    prior: Optional[str] = Field(
        None, description="A bundled prior's name or a weights file. Default: syrip12-scratch."
    )
    preset: Literal[tuple(PRESETS)] = Field(  # type: ignore[valid-type]
        DEFAULT_PRESET,
        description=f"{', '.join(PRESETS)}. fast: 20 prior steps, plausible bone lengths, bfloat16 products where the "
        "CPU has AMX/AVX512-BF16; faithful: the paper's 1000 steps, float32, 40-60x slower; fast-bf16 / "
        "fast-fp32: fast in bfloat16 / float32 on every device (fast-fp32: the same answer on every CPU; "
        "docs/lifting.md).",
    )
    steps: Optional[int] = Field(None, ge=1, le=MAX_STEPS, description="Prior iterations instead of the preset's.")
    temporal: Literal[TEMPORAL_MODES] = Field(  # type: ignore[valid-type]
        "none",
        description=f"For sequences: {', '.join(TEMPORAL_MODES)}. smooth: a Gaussian filter over time after "
        "lifting; two-pass: smooth, then 3 prior steps back onto the rays; clip: two-pass, then each track as one "
        "infant (one skeleton, limb bones at their length, depth sides kept, ambiguous stretches flagged).",
    )
    sigma: float = Field(
        DEFAULT_SIGMA_FRAMES, gt=0, le=MAX_SIGMA_FRAMES, description="Width of --temporal's Gaussian, in frames."
    )
    hypotheses: Optional[int] = Field(
        None,
        ge=1,
        le=MAX_HYPOTHESES,
        description=f"Solutions per instance (1 to {MAX_HYPOTHESES}); their spread sets uncertainty_m and "
        "hypothesis_spread_mm (over 80 mm: flagged unstable_solution). Default: the preset's (1).",
    )
    seed: int = Field(0, ge=0, le=MAX_SEED, description="Seed of the hypotheses: the same seed, the same poses.")
    calibration: PathOption = Field(
        None,
        description="Uncertainty calibration for a prior of your own (docs/uncertainty.md). Default: the bundled one.",
    )
    # Lifting, expert
    ray_weight: Optional[float] = Field(
        None,
        gt=0,
        le=1,
        description=f"Share of the way observed joints move onto their rays per step, (0, 1] "
        f"(fast: {_FAST.ray_weight:g}).",
    )
    ray_confidence_ratio: Optional[float] = Field(
        None,
        ge=0,
        le=1,
        description="Joints below this share of their pose's median confidence move in proportion, [0, 1] "
        f"(fast: {_FAST.ray_confidence_ratio:g}).",
    )
    hip_ray_factor: Optional[float] = Field(
        None, ge=0, le=1, description=f"The hips' share of that pull, [0, 1] (fast: {_FAST.hip_ray_factor:g})."
    )
    twin_rate: Optional[float] = Field(
        None,
        ge=0,
        le=1,
        description=f"Share of each left/right limb-length mismatch removed per step, [0, 1] "
        f"(fast: {_FAST.twin_rate:g}).",
    )
    proportion_rate: Optional[float] = Field(
        None,
        ge=0,
        le=1,
        description=f"Share of each bone's mismatch with the template's proportions removed per step, [0, 1] "
        f"(fast: {_FAST.proportion_rate:g}).",
    )
    twin_ratio_cap: Optional[float] = Field(
        None,
        ge=0,
        le=100,
        description=f"Limbs longer than this times their twin are brought to it; 0: off "
        f"(fast: {_FAST.twin_ratio_cap:g}).",
        json_schema_extra={"expected": "0 (off) or a number in [1, 100]"},
    )
    # Output
    output: Optional[str] = Field(
        None,
        description="Output file (one input), format from its extension; - for stdout. Default: "
        "<input stem>.zedo.json beside the input.",
    )
    output_dir: PathOption = Field(None, description="Write every output into this folder (made if missing).")
    output_format: Optional[Literal[OUTPUT_FORMATS]] = Field(  # type: ignore[valid-type]
        None,
        description=f"{', '.join(OUTPUT_FORMATS)} (trc, c3d: marker files, docs/exports.md). Default: from -o, "
        "else json.",
    )
    units: Literal[UNITS] = Field("m", description=f"{', '.join(UNITS)} (TRC is always m, C3D mm).")  # type: ignore[valid-type]
    frame: Literal[FRAMES] = Field(  # type: ignore[valid-type]
        "camera",
        description=f"{', '.join(FRAMES)}: camera axes (x right, y down, z forward), with the root at the origin "
        "for root.",
    )
    marker_axes: Literal[tuple(MARKER_AXES)] = Field(  # type: ignore[valid-type]
        "level",
        description=f"Axes of TRC / C3D files: {', '.join(MARKER_AXES)} (overhead: a camera above a lying infant).",
    )
    plot: PathOption = Field(None, description="Also write PNGs of three 3D poses into this folder.")
    save_hypotheses: bool = Field(False, description="Also write every hypothesis (JSON, NPZ).")
    overwrite: bool = Field(False, description="Replace outputs that exist.")
    quiet: bool = Field(False, description="No progress or summary on stderr.")
    # Performance
    device: str = Field("cpu", description=DEVICE_HELP)
    engine: Literal[ENGINES] = Field(  # type: ignore[valid-type]
        "local",
        description="local, or ray: the batch over a Ray cluster, the same outputs (pip install 'zedo[ray]').",
    )
    ray_address: Optional[str] = Field(
        None, description="The Ray cluster to join (else RAY_ADDRESS, else a local one)."
    )
    workers: Optional[int] = Field(
        None, ge=1, description="Ray workers (prior loads). Default: the CPUs / the local engine's threads."
    )

    @field_validator("skeleton")
    @classmethod
    def _a_joint_set(cls, value: str | None) -> str | None:
        if value is not None:
            try:
                get_skeleton(value)  # the joint sets' own refusal, by name
            except ConfigError as exc:
                raise ValueError(str(exc)) from None
        return value

    def check(self) -> None:
        cap = self.twin_ratio_cap
        if cap is not None and cap != 0 and cap < 1:
            raise ConfigError(f"--twin-ratio-cap must be {self.expected('twin_ratio_cap')}, got {show(cap)}")
        if self.camera is not None and self.intrinsics is None:
            raise ConfigError("--camera picks a camera of an --intrinsics file: give the file too")

    def lift_config(self) -> LiftConfig:
        """The preset's LiftConfig with the numbers these options set."""
        from dataclasses import replace

        changes = {k: getattr(self, k) for k in CONFIG_KEYS if getattr(self, k) is not None}
        return replace(PRESETS[self.preset], **changes)

    def rerun_values(self) -> dict[str, Any]:
        """What a result records of these options (JSON values: paths as strings, pairs as lists)."""
        out: dict[str, Any] = {}
        for key in RERUN_KEYS:
            value = getattr(self, key)
            out[key] = str(value) if isinstance(value, Path) else list(value) if isinstance(value, tuple) else value
        return out
