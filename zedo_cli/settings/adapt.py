"""`AdaptOptions`: every option of `zedo adapt`, for the command line and `--config`."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, ClassVar, Literal, Optional

from pydantic import Field

from ..data.datasets import SYRIP_SPLITS
from ..prior.schedules import ADAPT_TRAINING, STORED_DTYPES, STRATEGIES, WEIGHT_CHOICES
from .limits import DEVICE_HELP, MAX_SEED
from .model import Options

PathOption = Annotated[Optional[Path], Field(strict=False)]


class AdaptOptions(Options):
    """The settings of `zedo adapt`, one field per long option."""

    command: ClassVar[str] = "adapt"

    base: str = Field(
        "adult12-rotscale",
        description="Prior to adapt: a bundled name (adult12-rotscale, syrip12-scratch) or a weights file.",
    )
    strategy: Literal[STRATEGIES] = Field(  # type: ignore[valid-type]
        "control",
        description="control (frozen base + trainable branch), finetune (all weights from the base) or scratch "
        "(fresh net of the base's size).",
    )
    output: Annotated[Path, Field(strict=False)] = Field(
        Path("adapted.safetensors"), description="Weights file to write (.safetensors); `zedo lift --prior` loads it."
    )
    syrip_dir: PathOption = Field(None, description="Adapt on the SyRIP data folder instead of POSES.")
    split: Literal[SYRIP_SPLITS] = Field("train", description="SyRIP side: train (600 poses), test or all.")  # type: ignore[valid-type]
    skeleton: Optional[str] = Field(None, description="Joint set of POSES when its file does not name it.")
    add_poses: PathOption = Field(
        None, description="Also train on these poses (npz, e.g. from `zedo augment`), added after the --limit subset."
    )
    limit: Optional[int] = Field(
        None, ge=1, description="Train on a seeded, reproducible subset of N poses (default: all)."
    )
    epochs: Optional[int] = Field(
        None,
        ge=1,
        description="Passes over the data; one step each while N <= batch size. Default: 1000 (control, finetune), "
        "8000 (scratch).",
    )
    batch_size: int = Field(ADAPT_TRAINING.batch_size, ge=1, description="Poses per step.")
    lr: float = Field(ADAPT_TRAINING.lr, gt=0, le=1, description="Adam learning rate after warm-up.")
    warmup_steps: Optional[int] = Field(
        None, ge=0, description="Linear warm-up steps. Default: 200 (control, finetune), 5000 (scratch)."
    )
    seed: int = Field(
        0, ge=0, le=MAX_SEED, description="Seed of the --limit subset, new weights (prompt, scratch net), noise and "
        "shuffling.",
    )  # fmt: skip
    weights: Literal[WEIGHT_CHOICES] = Field(  # type: ignore[valid-type]
        "ema",
        description="Which weights to save: ema (moving average, the default: steadier on held-out poses) or raw "
        "(last step).",
    )
    dtype: Literal[STORED_DTYPES] = Field("float16", description="Stored precision: float16 or float32.")  # type: ignore[valid-type]
    license: Optional[str] = Field(
        None, description="Terms of POSES, stored with the base's terms (SyRIP's are filled in)."
    )
    device: str = Field("cpu", description=DEVICE_HELP)
    overwrite: bool = Field(False, description="Replace the output if it exists.")
    quiet: bool = Field(False, description="No progress bar.")
