"""`CalibrateOptions`: every option of `zedo calibrate`, for the command line and `--config`."""

from __future__ import annotations

from typing import ClassVar

from pydantic import Field

from ..camera.calibration import DEFAULT_VIDEO_FRAMES, MAX_RMS_PX, MIN_VIEWS, Board, CalibrationSettings
from .model import Options


class CalibrateOptions(Options):
    """The settings of `zedo calibrate`, one field per long option."""

    command: ClassVar[str] = "calibrate"

    board: str = Field(
        description="Inner corners COLSxROWS, where four squares meet (a board of 10 x 7 squares: 9x6).",
        pattern=r"^\s*\d+\s*[xX]\s*\d+\s*$",
        json_schema_extra={"expected": "COLSxROWS inner corners such as 9x6"},
    )
    square: float = Field(gt=0, description="Side of one square in metres (e.g. 0.025).")
    output: str = Field(description="The camera file: .yml / .yaml / .json / .xml (OpenCV FileStorage).")
    fisheye: bool = Field(False, description="Fit OpenCV's fisheye model (k1..k4) instead of the pinhole.")
    frames: int = Field(DEFAULT_VIDEO_FRAMES, ge=1, description="Frames sampled evenly from each video.")
    min_views: int = Field(MIN_VIEWS, ge=3, description="Refuse with fewer views where the board was found.")
    max_rms: float = Field(MAX_RMS_PX, gt=0, description="Refuse an RMS reprojection error above this, px.")
    k3: bool = Field(False, description="Pinhole: fit k3 as well (needs many views spread to the corners).")
    tangential: bool = Field(False, description="Pinhole: fit the tangential p1, p2 as well.")
    overwrite: bool = Field(False, description="Replace the output if it exists.")
    quiet: bool = Field(False, description="No progress bar or report on stderr.")

    def calibration_settings(self) -> CalibrationSettings:
        return CalibrationSettings(Board.parse(self.board, self.square), self.fisheye, self.min_views, self.max_rms,
                                   self.frames, self.k3, self.tangential)  # fmt: skip
