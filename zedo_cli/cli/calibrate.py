"""`zedo calibrate`: checkerboard views (images, videos) -> an OpenCV FileStorage camera file."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ..camera.calibration import (
    DEFAULT_VIDEO_FRAMES,
    MAX_RMS_PX,
    MIN_VIEWS,
    Board,
    Calibration,
    CalibrationSettings,
    calibrate_files,
)
from ..camera.calibration_writer import storage_format, write_calibration
from ..files import check_writable
from .common import err_console, error_boundary, output_option, step_progress


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
    board: Annotated[
        str,
        typer.Option(
            help="Inner corners COLSxROWS, where four squares meet (a board of 10 x 7 squares: 9x6).",
            show_default=False,
        ),  # fmt: skip
    ],
    square: Annotated[float, typer.Option(help="Side of one square in metres (e.g. 0.025).", show_default=False)],
    out: Annotated[str, output_option("The camera file: .yml / .yaml / .json / .xml (OpenCV FileStorage).")],
    fisheye: Annotated[bool, typer.Option(help="Fit OpenCV's fisheye model (k1..k4) instead of the pinhole.")] = False,
    frames: Annotated[int, typer.Option(help="Frames sampled evenly from each video.")] = DEFAULT_VIDEO_FRAMES,
    min_views: Annotated[int, typer.Option(help="Refuse with fewer views where the board was found.")] = MIN_VIEWS,
    max_rms: Annotated[float, typer.Option(help="Refuse an RMS reprojection error above this, px.")] = MAX_RMS_PX,
    k3: Annotated[bool, typer.Option(help="Pinhole: fit k3 as well (needs many views spread to the corners).")] = False,
    tangential: Annotated[bool, typer.Option(help="Pinhole: fit the tangential p1, p2 as well.")] = False,
    overwrite: Annotated[bool, typer.Option(help="Replace the output if it exists.")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No progress bar or report on stderr.")] = False,
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
    settings = CalibrationSettings(Board.parse(board, square), fisheye, min_views, max_rms, frames, k3, tangential)
    storage_format(out)
    check_writable(Path(out), overwrite)  # before any work
    with step_progress(quiet, "calibrate") as on_view:
        cal = calibrate_files(inputs, settings, on_view)
    write_calibration(out, cal, overwrite=overwrite)
    if not quiet:
        _report(cal, out)
