"""`zedo render`: a result's skeletons drawn over its footage (MP4 for a video, PNGs for images)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Optional

import typer

from ..errors import ConfigError, plural
from ..footage.render import RenderSettings, render_images, render_video
from ..formats.readers.result import read_result
from .common import err_console, error_boundary, output_option, step_progress


@error_boundary
def render_command(
    result: Annotated[
        str, typer.Argument(help="A zedo result, .json or .jsonl (zedo lift's output).", show_default=False)
    ],
    out: Annotated[str, output_option("An .mp4 file (with --video), or a folder for the PNGs (with --images).")],
    video: Annotated[
        Optional[Path], typer.Option(help="The video the keypoints came from (frame i <-> the result's frame_index i).")
    ] = None,
    images: Annotated[
        Optional[Path],
        typer.Option(help="The folder of images the keypoints came from (matched by file_name, else image_id)."),
    ] = None,
    side_view: Annotated[
        bool, typer.Option(help="Add a panel beside each frame: the skeletons from the side (depth against height).")
    ] = False,
    overwrite: Annotated[bool, typer.Option(help="Replace outputs that exist.")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No progress bar or summary on stderr.")] = False,
) -> None:
    """Draw the lifted skeletons over the footage, to see how well the 3D poses fit.

    Each person's 3D pose is projected through its frame's camera, lens distortion included,
    into the original image. Bones and joints are coloured by side (left blue, right orange,
    centre yellow); joints the prior filled in (not observed in 2D) are hollow rings; a person
    with flags gets a magenta box and the flags' names; persons not lifted are listed. Frames
    carry a stamp: frame index, and time when the frame rate is known. Frames the result does
    not mention pass through unchanged.

    Examples:

      zedo render clip.zedo.json --video clip.mp4 -o clip.render.mp4

      zedo render photos.zedo.json --images photos/ -o rendered/ --side-view
    """
    if (video is None) == (images is None):
        raise ConfigError("give exactly one of --video FILE and --images DIR")
    res = read_result(result)
    settings = RenderSettings(side_view, overwrite)
    with step_progress(quiet, "render") as on_frame:
        if video is not None:
            summary = render_video(res, video, out, settings, on_frame)
        else:
            summary = render_images(res, images, out, settings, on_frame)
    if not quiet:
        rate = summary.frames / summary.seconds if summary.seconds > 0 else float("nan")
        wrote = summary.output if video is not None else f"{plural(summary.frames, 'PNG')} into {summary.output}"
        err_console.print(f"rendered {plural(summary.frames, 'frame')} ({summary.drawn} with people, "
                          f"{plural(summary.persons, 'skeleton')}) in {summary.seconds:.1f} s ({rate:.0f} frames/s); "
                          f"wrote {wrote}", markup=False, soft_wrap=True)  # fmt: skip
