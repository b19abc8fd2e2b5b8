"""`FitAugmenterOptions` and `AugmentOptions`: every option of `zedo fit-augmenter` and `zedo augment`, for the
command line and `--config`."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Annotated, ClassVar, Literal, Optional

from pydantic import Field

from ..data.datasets import SYRIP_SPLITS
from ..errors import ConfigError
from ..prior.schedules import AUGMENTER_TRAINING, SCALE_MODES, STORED_DTYPES, WEIGHT_CHOICES, TrainConfig
from .limits import DEVICE_HELP, MAX_COUNT, MAX_SEED, MAX_STEPS
from .model import Options

PathOption = Annotated[Optional[Path], Field(strict=False)]
ORIENT_MODES = ("keep", "infant")
BONE_MODES = ("keep", "infant")
DEFAULT_STRENGTH = 0.2  # the smallest sweep strength closing >= 90 % of the proportion gap (docs/benchmarks.md)
INFANT_SOURCES = "--infant (an npz file) or --syrip-dir"


def check_one_infant_source(infant: Path | None, syrip_dir: Path | None) -> None:
    if infant is not None and syrip_dir is not None:
        raise ConfigError(f"give at most one infant source: {INFANT_SOURCES}")


class FitAugmenterOptions(Options):
    """The settings of `zedo fit-augmenter`, one field per long option."""

    command: ClassVar[str] = "fit-augmenter"

    infant: PathOption = Field(None, description="Infant 3D poses (npz with 'poses' (N,J,3) in metres, 'joint_names').")
    syrip_dir: PathOption = Field(None, description="Take the infant poses from the SyRIP data folder instead.")
    split: Literal[SYRIP_SPLITS] = Field("train", description="SyRIP side: train (600 poses), test or all.")  # type: ignore[valid-type]
    adult_dir: PathOption = Field(None, description="Adult motion-capture folder (three *_h36m17.npz files).")
    adult_poses: PathOption = Field(None, description="Adult 3D poses as an npz file, instead of --adult-dir.")
    skeleton: str = Field("syrip12", description="Joint set of the model (the infant data's).")
    init: str = Field(
        "adult12-rotscale",
        description="Start from this plain prior (bundled name or file), or 'none' for fresh weights.",
    )
    output: Annotated[Path, Field(strict=False)] = Field(
        Path("augmenter.safetensors"), description="Augmenter weights file to write (.safetensors)."
    )
    epochs: int = Field(AUGMENTER_TRAINING.epochs, ge=1, description="Passes over the balanced adult + infant set.")
    batch_size: int = Field(
        AUGMENTER_TRAINING.batch_size, ge=1, description="Poses per step (half adult, half infant on average)."
    )
    lr: float = Field(AUGMENTER_TRAINING.lr, gt=0, le=1, description="Adam learning rate after warm-up.")
    warmup_steps: int = Field(AUGMENTER_TRAINING.warmup_steps, ge=0, description="Linear warm-up steps.")
    seed: int = Field(
        0, ge=0, le=MAX_SEED, description="Seed of the tokens, fresh weights, rotations, noise and shuffling."
    )
    weights: Literal[WEIGHT_CHOICES] = Field(  # type: ignore[valid-type]
        "ema", description="Which weights to save: ema (moving average) or raw (last step)."
    )
    dtype: Literal[STORED_DTYPES] = Field("float16", description="Stored precision: float16 or float32.")  # type: ignore[valid-type]
    license: Optional[str] = Field(
        None, description="Terms of the infant data (SyRIP's are filled in); the adult terms are added."
    )
    device: str = Field("cpu", description=DEVICE_HELP)
    overwrite: bool = Field(False, description="Replace the output if it exists.")
    quiet: bool = Field(False, description="No progress bar.")

    def check(self) -> None:
        check_one_infant_source(self.infant, self.syrip_dir)
        if self.infant is None and self.syrip_dir is None:
            raise ConfigError(f"give the infant poses: {INFANT_SOURCES}")
        if (self.adult_poses is None) == (self.adult_dir is None):
            raise ConfigError("give exactly one adult source: --adult-poses (an npz file) or --adult-dir")

    def training(self) -> TrainConfig:
        """The training settings: `AUGMENTER_TRAINING` with these options'."""
        return replace(AUGMENTER_TRAINING, epochs=self.epochs, batch_size=self.batch_size, lr=self.lr,
                       warmup_steps=self.warmup_steps, seed=self.seed)  # fmt: skip


class AugmentOptions(Options):
    """The settings of `zedo augment`, one field per long option."""

    command: ClassVar[str] = "augment"

    model: Annotated[Path, Field(strict=False)] = Field(
        Path("augmenter.safetensors"), description="Augmenter weights file written by `zedo fit-augmenter`."
    )
    adult_dir: PathOption = Field(
        None, description="Convert poses of the adult motion-capture folder instead of ADULT_POSES."
    )
    count: int = Field(
        600,
        ge=1,
        le=MAX_COUNT,
        description="Number of poses to write, drawn from the adult poses (seeded; without repeats when there are "
        "enough).",
    )
    output: Annotated[Path, Field(strict=False)] = Field(
        Path("augmented.npz"),
        description="npz file to write: 'poses' (count, J, 3) metres, 'joint_names', 'names', 'source_poses'.",
    )
    strength: float = Field(
        DEFAULT_STRENGTH,
        ge=0,
        le=1,
        description="Noise level t0 in (0, 1]: higher changes more (proportions, then posture); 0 only resizes.",
    )
    steps: int = Field(100, ge=1, le=MAX_STEPS, description="Reverse diffusion steps from t0.")
    scale: Literal[SCALE_MODES] = Field(  # type: ignore[valid-type]
        "infant",
        description="Size of the outputs: infant (drawn from the infant training sizes stored in the model) or keep "
        "(each input's own size).",
    )
    orient: Literal[ORIENT_MODES] = Field(  # type: ignore[valid-type]
        "keep",
        description="keep (the input's orientation) or infant (turn each pose's torso like a random pose of --infant "
        "/ --syrip-dir).",
    )
    bones: Literal[BONE_MODES] = Field(  # type: ignore[valid-type]
        "keep",
        description="keep (the converted bone lengths) or infant (each pose takes the bone proportions of a random "
        "pose of --infant / --syrip-dir, keeping its joint angles and size).",
    )
    infant: PathOption = Field(
        None, description="Infant reference poses (npz) for --orient infant, --bones infant and --plot."
    )
    syrip_dir: PathOption = Field(None, description="Use SyRIP's training poses as the infant reference.")
    plot: PathOption = Field(
        None,
        description="Folder for PNGs: bone-length and bone-angle distributions (infant, augmented, adult) and "
        "adult/converted pairs.",
    )
    seed: int = Field(
        0, ge=0, le=MAX_SEED, description="Seed of the pose draw, noise, sizes, bone proportions and orientations."
    )
    overwrite: bool = Field(False, description="Replace the output and the PNGs if they exist.")
    quiet: bool = Field(False, description="No progress bar.")

    def check(self) -> None:
        check_one_infant_source(self.infant, self.syrip_dir)
        if self.infant is None and self.syrip_dir is None and self.needs_reference():
            raise ConfigError(
                f"--orient infant, --bones infant and --plot need infant reference poses: {INFANT_SOURCES}"
            )

    def needs_reference(self) -> bool:
        """Whether the conversion reads infant reference poses."""
        return self.orient == "infant" or self.bones == "infant" or self.plot is not None
