"""`EvaluateOptions`, `BenchmarkOptions` and `BenchmarkSymmetryOptions`: every option of `zedo evaluate`,
`zedo benchmark` and `zedo benchmark-symmetry`, for the command line and `--config`."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Annotated, ClassVar, Literal, Optional

from pydantic import AfterValidator, Field, field_validator

from ..analysis.pose.symmetry import DEFAULT_THRESHOLD_DEG
from ..data.datasets import SCORING_PROTOCOLS, SYRIP_SPLITS
from ..errors import ConfigError
from ..lifting.config import DEFAULT_PRESET, MAX_HYPOTHESES, PRESETS, LiftConfig
from .limits import DEVICE_HELP, MAX_SYMMETRY_THRESHOLD_DEG, REPORT_OUTPUT_HELP
from .model import Options

PathOption = Annotated[Optional[Path], Field(strict=False)]
INPUTS_2D = ("gt", "detected")  # the 2D inputs of the SyRIP benchmarks: ground truth, FiDIP detections
INPUTS_EXPECTED = {"expected": "gt, detected or gt,detected"}
MAX_SCALE_POSES = 10_000_000  # poses of one `zedo benchmark --scale` run
MAX_FIT_EPOCHS = 100_000  # epochs of the timed training
MAX_CHUNK_ROWS = 1 << 20  # rows lifted together
# The recipe `--fit-recipe` defaults to: the bundled prior's, in the source tree (not installed with the package).
BUNDLED_RECIPE = Path(__file__).resolve().parents[2] / "weights_spec" / "syrip12-scratch.toml"


def input_list(inputs: str) -> tuple[str, ...]:
    """`--inputs gt,detected` as ("gt", "detected")."""
    return tuple(i.strip() for i in inputs.split(","))


def _inputs(value: str) -> str:
    if any(i not in INPUTS_2D for i in input_list(value)):
        raise ValueError(f"--inputs must list gt and/or detected, got {value!r}")
    return value


def _presets(value: tuple[str, ...]) -> tuple[str, ...]:
    if not value:
        raise ValueError(f"--preset must be one or more of {', '.join(PRESETS)}, got none")
    for name in value:
        if name not in PRESETS:
            raise ValueError(f"--preset must be one of {', '.join(PRESETS)}, got {name!r}")
    return value


def _scale_sizes(value: tuple[int, ...]) -> tuple[int, ...]:
    for n in value:
        if not 1 <= n <= MAX_SCALE_POSES:
            raise ValueError(f"--scale must be an integer in [1, {MAX_SCALE_POSES}], got {n}")
    return value


Inputs2D = Annotated[str, AfterValidator(_inputs)]


class EvaluateOptions(Options):
    """The settings of `zedo evaluate`, one field per long option."""

    command: ClassVar[str] = "evaluate"

    syrip_dir: PathOption = Field(None, description="Score against the SyRIP 3D ground truth in this folder.")
    split: Literal[SYRIP_SPLITS] = Field("test", description="SyRIP split holding the images: test, train or all.")  # type: ignore[valid-type]
    gt: PathOption = Field(
        None,
        description="Or: ground truth npz ('poses' (N,J,3) m, 'joint_names', 'names' = file names or image ids).",
    )
    protocol: Literal[tuple(SCORING_PROTOCOLS)] = Field(  # type: ignore[valid-type]
        "syrip12", description=f"Joint set scored, both sides centred on its root: {', '.join(SCORING_PROTOCOLS)}."
    )
    as_json: bool = Field(False, alias="json", description="Print the scores as JSON on stdout.")
    output: Optional[str] = Field(None, description=REPORT_OUTPUT_HELP)
    overwrite: bool = Field(False, description="Replace the output if it exists.")
    quiet: bool = Field(False, description="No note on stderr.")

    def check(self) -> None:
        if (self.syrip_dir is None) == (self.gt is None):
            raise ConfigError("give the ground truth as either --syrip-dir or --gt")


class BenchmarkOptions(Options):
    """The settings of `zedo benchmark` (Test100, or the device benchmark with --scale), one field per long option."""

    command: ClassVar[str] = "benchmark"

    syrip_dir: PathOption = Field(
        None, description="The SyRIP data folder (e.g. ../shared/data/syrip); with --scale optional (pose source)."
    )
    prior: Optional[str] = Field(None, description="A bundled prior's name or a weights file.")
    preset: Annotated[tuple[str, ...], AfterValidator(_presets)] = Field(
        ("faithful", "fast"),
        description=f"Lifting preset(s) to run, repeatable; the first is the baseline of the ratios: "
        f"{', '.join(PRESETS)}.",
        json_schema_extra={"expected": f"one or more of {', '.join(PRESETS)}"},
    )
    inputs: Inputs2D = Field(
        "gt,detected", description="2D inputs: gt, detected or gt,detected.", json_schema_extra=INPUTS_EXPECTED
    )
    throughput: bool = Field(
        True, description="Also time each preset on all 700 real images x (gt, detected) = 1400 poses in one batch."
    )
    hypotheses: Optional[int] = Field(
        None,
        ge=1,
        le=MAX_HYPOTHESES,
        description="Override every preset's hypotheses per instance (zedo lift --hypotheses).",
    )
    device: str = Field("cpu", description=DEVICE_HELP)
    scale: Annotated[tuple[int, ...], AfterValidator(_scale_sizes)] = Field(
        (),
        description="Instead of Test100: the device benchmark, lifting this many synthetic poses (repeatable; "
        "on a GPU: --scale 100000 --scale 1000000), with peak memory, CPU agreement and fit-prior time.",
        json_schema_extra={"expected": f"integers in [1, {MAX_SCALE_POSES}]"},
    )
    scale_preset: Literal[tuple(PRESETS)] = Field("fast", description="With --scale: the preset lifted.")  # type: ignore[valid-type]
    agreement_poses: int = Field(
        100_000,
        ge=0,
        le=MAX_SCALE_POSES,
        description="With --scale: the first this many poses are lifted on the CPU too and compared (0: skip).",
    )
    fit_epochs: int = Field(
        200,
        ge=0,
        le=MAX_FIT_EPOCHS,
        description="With --scale: epochs of the bundled recipe's training timed on the device (0: skip).",
        json_schema_extra={"expected": f"0 (skip) or an integer in [2, {MAX_FIT_EPOCHS}]"},
    )
    fit_recipe: PathOption = Field(
        None, description="With --scale: the recipe timed (default: weights_spec/syrip12-scratch.toml)."
    )
    chunk_size: Optional[int] = Field(
        None, ge=1, le=MAX_CHUNK_ROWS, description="With --scale: rows lifted together (the preset's: 4096)."
    )
    as_json: bool = Field(False, alias="json", description="Print the scores as JSON on stdout.")
    output: Optional[str] = Field(None, description=REPORT_OUTPUT_HELP)
    overwrite: bool = Field(False, description="Replace the output if it exists.")
    quiet: bool = Field(False, description="No progress bar.")

    @field_validator("fit_epochs")
    @classmethod
    def _timed_epochs(cls, value: int) -> int:
        if value == 1:  # the first epoch warms up and is not timed
            raise ValueError("--fit-epochs must be 0 (skip) or at least 2: the first epoch is not timed")
        return value

    def check(self) -> None:
        if not self.scale and self.syrip_dir is None:
            raise ConfigError("--syrip-dir is needed (the SyRIP data folder), unless --scale is given")

    def inputs_2d(self) -> tuple[str, ...]:
        return input_list(self.inputs)

    def lift_configs(self) -> dict[str, LiftConfig]:
        """Each --preset once, in order (the first is the baseline), with --hypotheses where given."""
        configs = {name: PRESETS[name] for name in dict.fromkeys(self.preset)}
        if self.hypotheses is None:
            return configs
        return {name: replace(cfg, hypotheses=self.hypotheses) for name, cfg in configs.items()}

    def scale_config(self) -> LiftConfig:
        """--scale-preset's LiftConfig, with --chunk-size where given."""
        config = PRESETS[self.scale_preset]
        return config if self.chunk_size is None else replace(config, chunk_size=self.chunk_size)

    def recipe_path(self) -> Path:
        return self.fit_recipe or BUNDLED_RECIPE


class BenchmarkSymmetryOptions(Options):
    """The settings of `zedo benchmark-symmetry`, one field per long option."""

    command: ClassVar[str] = "benchmark-symmetry"

    syrip_dir: Annotated[Path, Field(strict=False)] = Field(
        description="The SyRIP data folder (e.g. ../shared/data/syrip)."
    )
    prior: Optional[str] = Field(None, description="A bundled prior's name or a weights file (syrip12).")
    preset: Literal[tuple(PRESETS)] = Field(DEFAULT_PRESET, description=f"Lifting preset: {', '.join(PRESETS)}.")  # type: ignore[valid-type]
    inputs: Inputs2D = Field(
        "gt,detected", description="2D inputs: gt, detected or gt,detected.", json_schema_extra=INPUTS_EXPECTED
    )
    symmetry_threshold: float = Field(
        DEFAULT_THRESHOLD_DEG, ge=0, le=MAX_SYMMETRY_THRESHOLD_DEG, description="Threshold of the calls, degrees."
    )
    reference: bool = Field(
        True, description="Also score HW-HuP's 3D predictions (the weak truth's origin) as a reference."
    )
    device: str = Field("cpu", description=DEVICE_HELP)
    as_json: bool = Field(False, alias="json", description="Print the figures as JSON on stdout.")
    output: Optional[str] = Field(None, description=REPORT_OUTPUT_HELP)
    overwrite: bool = Field(False, description="Replace the output if it exists.")
    quiet: bool = Field(False, description="No progress bar.")

    def inputs_2d(self) -> tuple[str, ...]:
        return input_list(self.inputs)
