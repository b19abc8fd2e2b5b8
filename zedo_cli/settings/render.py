"""`RenderOptions`: every option of `zedo render`, for the command line and `--config`."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, ClassVar, Optional

from pydantic import Field

from ..errors import ConfigError
from .limits import MAX_FPS
from .model import Options

PathOption = Annotated[Optional[Path], Field(strict=False)]


class RenderOptions(Options):
    """The settings of `zedo render`, one field per long option."""

    command: ClassVar[str] = "render"

    output: str = Field(description="An .mp4 file (with --video), or a folder for the PNGs (with --images).")
    video: PathOption = Field(
        None, description="The video the keypoints came from (frame i <-> the result's frame_index i)."
    )
    images: PathOption = Field(
        None, description="The folder of images the keypoints came from (matched by file_name, else image_id)."
    )
    fps: Optional[float] = Field(
        None,
        gt=0,
        le=MAX_FPS,
        description="The video's frame rate, needed where its file stores none (a raw MJPEG or H.264 stream). "
        "Default: the video's.",
    )
    side_view: bool = Field(
        False, description="Add a panel beside each frame: the skeletons from the side (depth against height)."
    )
    overwrite: bool = Field(False, description="Replace outputs that exist.")
    quiet: bool = Field(False, description="No progress bar or summary on stderr.")

    def check(self) -> None:
        if (self.video is None) == (self.images is None):
            raise ConfigError("give exactly one of --video FILE and --images DIR")
