"""`zedo render`: a result's skeletons drawn over its footage (MP4 for a video, PNGs for images)."""

from __future__ import annotations

from functools import partial
from pathlib import Path
from typing import Annotated, Optional

import typer

from ..errors import plural
from ..footage.render import RenderSettings, render_images, render_video
from ..formats.readers.result import read_result
from ..settings.render import RenderOptions
from .common import err_console, error_boundary, output_option, step_progress
from .config import config_option, model_option, print_config_option, resolve_options

_opt = partial(model_option, RenderOptions)  # the option `key` of RenderOptions, with the model's help text


@error_boundary
def render_command(
    result: Annotated[
        str, typer.Argument(help="A zedo result, .json or .jsonl (zedo lift's output).", show_default=False)
    ],
    out: Annotated[str, output_option(RenderOptions.help("output"))],
    video: Annotated[Optional[Path], _opt("video")] = None,
    images: Annotated[Optional[Path], _opt("images")] = None,
    fps: Annotated[Optional[float], _opt("fps")] = None,
    side_view: Annotated[bool, _opt("side_view")] = False,
    overwrite: Annotated[bool, _opt("overwrite")] = False,
    quiet: Annotated[bool, _opt("quiet", "--quiet", "-q")] = False,
    config: Annotated[Optional[Path], config_option("render")] = None,
    print_config: Annotated[bool, print_config_option()] = False,
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
    o: RenderOptions = resolve_options(RenderOptions).options
    res = read_result(result)
    settings = RenderSettings(o.side_view, o.overwrite, o.fps)
    with step_progress(o.quiet, "render") as on_frame:
        if o.video is not None:
            summary = render_video(res, o.video, o.output, settings, on_frame)
        else:
            summary = render_images(res, o.images, o.output, settings, on_frame)
    if not o.quiet:
        rate = summary.frames / summary.seconds if summary.seconds > 0 else float("nan")
        wrote = summary.output if o.video is not None else f"{plural(summary.frames, 'PNG')} into {summary.output}"
        err_console.print(f"rendered {plural(summary.frames, 'frame')} ({summary.drawn} with people, "
                          f"{plural(summary.persons, 'skeleton')}) in {summary.seconds:.1f} s ({rate:.0f} frames/s); "
                          f"wrote {wrote}", markup=False, soft_wrap=True)  # fmt: skip
