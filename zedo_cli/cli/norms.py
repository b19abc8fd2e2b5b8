"""`zedo norms`: a reference of typical infants from their clips, for `zedo analyze --norms`."""

from __future__ import annotations

from functools import partial
from pathlib import Path
from typing import Annotated, Optional

import typer

from ..analysis.analyse import AnalysisSettings, analyse
from ..analysis.compare import features_by_person
from ..analysis.norms.norms import MIN_REFERENCE_CLIPS, build_norms
from ..analysis.norms.norms_file import write_norms
from ..errors import ConfigError, plural
from ..files import check_writable
from ..formats.readers.result import read_result
from ..settings.norms import NormsOptions
from ..version import __version__
from .analyze import expand_results
from .common import err_console, error_boundary, output_option, progress_bar
from .config import config_option, model_option, print_config_option, resolve_options

_opt = partial(model_option, NormsOptions)  # the option `key` of NormsOptions, with the model's help text


@error_boundary
def norms_command(
    results: Annotated[
        list[str],
        typer.Argument(
            help="zedo results of clips of typical infants (from zedo lift --fps): files, folders, glob patterns.",
            show_default=False,
        ),
    ],
    output: Annotated[str, output_option(NormsOptions.help("output"))] = "norms.json",
    age_weeks: Annotated[Optional[list[float]], _opt("age_weeks")] = None,
    fps: Annotated[Optional[float], _opt("fps")] = None,
    overwrite: Annotated[bool, _opt("overwrite")] = False,
    quiet: Annotated[bool, _opt("quiet", "--quiet", "-q")] = False,
    config: Annotated[Optional[Path], config_option("norms")] = None,
    print_config: Annotated[bool, print_config_option()] = False,
) -> None:
    """Build a reference of typical infants for zedo analyze --norms.

    Analyses each clip as zedo analyze does and fits, per clip feature and
    age bracket, a normal distribution by maximum likelihood (Chambers et
    al. 2020). Each person track of a clip is one reference clip; at least
    20 per bracket (fewer are refused), of about the length of the clips you
    will compare. The reference keeps every clip's features, so that a
    clip missing a feature is compared on the features it has. Lift the
    reference's clips and the clips you compare alike (prior, preset,
    --temporal, kind of camera): the 3D features depend on it, and each
    reference clip records how it was lifted.

    Examples:

      zedo norms typical/ -o norms.json
      zedo norms a.zedo.json b.zedo.json ... --age-weeks 8 --age-weeks 14 ...
      zedo analyze infant.zedo.json --norms norms.json --age-weeks 12
    """
    o: NormsOptions = resolve_options(NormsOptions).options
    check_writable(Path(o.output), o.overwrite)
    sources = expand_results(results)
    ages = o.ages_per_input(len(sources))
    settings = AnalysisSettings(fps=o.fps)
    clips = []
    with progress_bar(o.quiet) as bar:
        task = bar.add_task("analyse clips", total=len(sources), status="")
        for source, age in zip(sources, ages, strict=True):
            a = analyse(read_result(source), settings)
            if not a.is_sequence:
                raise ConfigError(f"{source}: no fps (neither --fps nor recorded by zedo lift --fps): a reference "
                                  "is built from clips")  # fmt: skip
            clips += features_by_person(a, age)
            bar.update(task, advance=1)
    norms = build_norms(clips, __version__)
    write_norms(o.output, norms, overwrite=o.overwrite)
    if not o.quiet:
        for bracket in norms.brackets:
            n = norms.brackets_of_clips.count(bracket)
            fitted, left = len(norms.fits[bracket]), len(norms.left_out[bracket])
            err_console.print(f"bracket {bracket}: {plural(n, 'clip')}, {plural(fitted, 'feature')} fitted, "
                              f"{left} without a usable fit (fewer than {MIN_REFERENCE_CLIPS} values, or no "
                              "spread)", markup=False, soft_wrap=True)  # fmt: skip
        liftings = sorted({c.lifting for c in norms.clips if c.lifting is not None})
        if len(liftings) > 1:  # 3D features measured in several ways are pooled: the user should know
            err_console.print(f"zedo: note: the clips were lifted in {len(liftings)} ways ({'; '.join(liftings)}): "
                              "their 3D features are measured differently; lift a reference alike",
                              markup=False, soft_wrap=True)  # fmt: skip
        err_console.print(f"wrote {o.output}", markup=False, soft_wrap=True)
