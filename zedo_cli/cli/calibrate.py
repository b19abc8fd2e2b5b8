"""`zedo calibrate`: checkerboard views (images, videos) -> an OpenCV FileStorage camera file."""

from __future__ import annotations

from functools import partial
from pathlib import Path
from typing import Annotated, Optional

import typer

from ..camera.calibration import (
    DEFAULT_VIDEO_FRAMES,
    MAX_RMS_PX,
    MIN_VIEWS,
    Calibration,
    calibrate_files,
)
from ..camera.calibration_writer import storage_format, write_calibration
from ..files import check_writable
from ..settings.calibrate import CalibrateOptions
from .common import err_console, error_boundary, output_option, step_progress
from .config import config_option, model_option, print_config_option, resolve_options

_opt = partial(model_option, CalibrateOptions)  # the option `key` of CalibrateOptions, with the model's help text


def _report(cal: Calibration, output: str) -> None:
    cam = cal.camera
    coefficients = " ".join(f"{c:.4g}" for c in cam.dist)
    err_console.print(f"{cam.model} camera: fx {cam.fx:.2f} fy {cam.fy:.2f} cx {cam.cx:.2f} cy {cam.cy:.2f} px, "
                      f"distortion [{coefficients}]", markup=False, soft_wrap=True)  # fmt: skip
    err_console.print(f"RMS reprojection error {cal.rms:.3f} px over {len(cal.view_errors)} views", markup=False)
    for name, error in cal.view_errors:
        err_console.print(f"  {error:6.3f} px  {name}", markup=False, soft_wrap=True)
    if cal.views_without_board:
        err_console.print(f"board not found in {len(cal.views_without_board)} views: "
                          + ", ".join(cal.views_without_board), markup=False, soft_wrap=True)  # fmt: skip
    err_console.print(f"wrote {output}", markup=False, soft_wrap=True)


@error_boundary
def calibrate_command(
    inputs: Annotated[
        list[str],
        typer.Argument(
            help="Images of the board, folders of images, or videos (frames sampled evenly).", show_default=False
        ),  # fmt: skip
    ],
    board: Annotated[str, _opt("board", show_default=False)],
    square: Annotated[float, _opt("square", show_default=False)],
    out: Annotated[str, output_option(CalibrateOptions.help("output"))],
    fisheye: Annotated[bool, _opt("fisheye")] = False,
    frames: Annotated[int, _opt("frames")] = DEFAULT_VIDEO_FRAMES,
    min_views: Annotated[int, _opt("min_views")] = MIN_VIEWS,
    max_rms: Annotated[float, _opt("max_rms")] = MAX_RMS_PX,
    k3: Annotated[bool, _opt("k3")] = False,
    tangential: Annotated[bool, _opt("tangential")] = False,
    overwrite: Annotated[bool, _opt("overwrite")] = False,
    quiet: Annotated[bool, _opt("quiet", "--quiet", "-q")] = False,
    config: Annotated[Optional[Path], config_option("calibrate")] = None,
    print_config: Annotated[bool, print_config_option()] = False,
) -> None:
    """Calibrate a camera from views of a printed checkerboard.

    The board's inner corners are found in each view (OpenCV findChessboardCorners, refined by
    cornerSubPix), then OpenCV calibrateCamera fits focal lengths, principal point and k1, k2
    (--k3, --tangential: more), or cv2.fisheye.calibrate with --fisheye. Show the board at
    many positions and tilts, the image corners included.

    The RMS and per-view reprojection errors are reported, and the views where no board was
    found. Refused (exit code 6, nothing written): the board in no view or in fewer than
    --min-views, or an RMS above --max-rms. A video that cannot be opened: exit code 3.

    The output is OpenCV FileStorage (camera_matrix, distortion_coefficients, image_width,
    image_height, model, rms), which `zedo lift --intrinsics` and OpenCV read.

    Examples:

      zedo calibrate board/*.png --board 9x6 --square 0.025 -o cam.yml

      zedo calibrate board.mp4 --board 9x6 --square 0.025 --frames 40 -o cam.yml
    """
    o: CalibrateOptions = resolve_options(CalibrateOptions).options
    settings = o.calibration_settings()
    storage_format(o.output)
    check_writable(Path(o.output), o.overwrite)  # before any work
    with step_progress(o.quiet, "calibrate") as on_view:
        cal = calibrate_files(inputs, settings, on_view)
    write_calibration(o.output, cal, overwrite=o.overwrite)
    if not o.quiet:
        _report(cal, o.output)
