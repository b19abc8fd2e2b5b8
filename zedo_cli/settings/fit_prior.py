"""`FitPriorOptions`: every option of `zedo fit-prior`, for the command line and `--config`."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, ClassVar, Literal, Optional

from pydantic import Field

from ..data.datasets import SYRIP_SPLITS
from ..data.minirgbd import MAPPINGS, SPLITS
from ..prior.schedules import STORED_DTYPES, WEIGHT_CHOICES
from .limits import DEVICE_HELP, MAX_SEED
from .model import Options

PathOption = Annotated[Optional[Path], Field(strict=False)]


class FitPriorOptions(Options):
    """The settings of `zedo fit-prior`, one field per long option; the training options left unset take the
    recipe's values (`--recipe`, else the reference's)."""

    command: ClassVar[str] = "fit-prior"

    output: Annotated[Path, Field(strict=False)] = Field(
        Path("prior.safetensors"), description="Weights file to write (.safetensors)."
    )
    syrip_dir: PathOption = Field(None, description="Train on the SyRIP data folder instead of POSES.")
    split: Literal[SYRIP_SPLITS] = Field(  # type: ignore[valid-type]
        "train",
        description="Side of the split: train, test or all (SyRIP: 600, 100, 700 poses; MINI-RGBD: see "
        "--minirgbd-split).",
    )
    minirgbd_dir: PathOption = Field(
        None, description="Train on a local MINI-RGBD folder (holding 01 .. 12), mapped to h36m17."
    )
    minirgbd_split: Literal[tuple(SPLITS)] = Field(  # type: ignore[valid-type]
        "paper", description="MINI-RGBD sequences: paper (train 01-09, test 10-12) or reference (train 01-10, test "
        "11-12).",
    )  # fmt: skip
    mapping: Literal[tuple(MAPPINGS)] = Field(  # type: ignore[valid-type]
        "reference",
        description="MINI-RGBD SMIL -> h36m17 joints: reference (toes as ankles, collars as shoulders, as the "
        "authors) or anatomical.",
    )
    adult_dir: PathOption = Field(
        None,
        description="Train on the adult motion-capture folder (three *_h36m17.npz files), in --skeleton's joints "
        "(default syrip12).",
    )
    skeleton: Optional[str] = Field(
        None, description="Joint set of POSES when its file does not name it (h36m17, syrip12, ...)."
    )
    recipe: PathOption = Field(None, description="TOML recipe (see weights_spec/); options below override it.")
    epochs: Optional[int] = Field(None, ge=1, description="Passes over the data (recipe: 8000).")
    batch_size: Optional[int] = Field(None, ge=1, description="Poses per step (recipe: 5000).")
    lr: Optional[float] = Field(None, gt=0, le=1, description="Adam learning rate after warm-up (2e-4).")
    warmup_steps: Optional[int] = Field(None, ge=0, description="Linear warm-up steps (5000).")
    seed: Optional[int] = Field(
        None, ge=0, le=MAX_SEED, description="Seed of initial weights, shuffling and noise (0)."
    )
    weights: Optional[Literal[WEIGHT_CHOICES]] = Field(  # type: ignore[valid-type]
        None, description="Which weights to save: raw (last step, as the reference) or ema."
    )
    dtype: Optional[Literal[STORED_DTYPES]] = Field(  # type: ignore[valid-type]
        None, description="Stored precision: float16 (half the size) or float32."
    )
    license: Optional[str] = Field(
        None, description="Terms of the training data, stored in the file (SyRIP's are filled in)."
    )
    device: str = Field("cpu", description=DEVICE_HELP)
    ema_out: PathOption = Field(
        None, description="Also write the EMA weights to this file (to compare with the raw ones)."
    )
    overwrite: bool = Field(False, description="Replace the output if it exists.")
    quiet: bool = Field(False, description="No progress bar.")
