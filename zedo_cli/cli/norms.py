"""`zedo norms`: a reference of typical infants from their clips, for `zedo analyze --norms`."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Optional

import typer

from ..analysis.analyse import AnalysisSettings, analyse
from ..analysis.compare import features_by_person
from ..analysis.norms.norms import AGE_THRESHOLD_WEEKS, MIN_REFERENCE_CLIPS, build_norms, check_age_weeks
from ..analysis.norms.norms_file import write_norms
from ..errors import ConfigError, plural
from ..files import check_writable
from ..formats.readers.result import read_result
from ..version import __version__
from .analyze import expand_results
from .common import err_console, error_boundary, output_option, progress_bar


def ages_per_input(ages: list[float] | None, count: int) -> list[float | None]:
    """--age-weeks: none, one age for every input, or one per input in order."""
    if not ages:
        return [None] * count
    for age in ages:
        check_age_weeks(age)
    if len(ages) == 1:
        return [ages[0]] * count
    if len(ages) != count:
        raise ConfigError(f"--age-weeks: give one age for every clip or one per clip ({count}), got {len(ages)}")
    return list(ages)


@error_boundary
def norms_command(
    results: Annotated[
        list[str],
        typer.Argument(
            help="zedo results of clips of typical infants (from zedo lift --fps): files, folders, glob patterns.",
            show_default=False,
        ),
    ],
    output: Annotated[str, output_option("The reference to write (.json).")] = "norms.json",
    age_weeks: Annotated[
        Optional[list[float]],
        typer.Option(
            help=f"Age in weeks: once (every clip) or once per clip, in order. With ages, the reference is "
            f"split at {AGE_THRESHOLD_WEEKS:g} weeks as published; without, one bracket."
        ),
    ] = None,
    fps: Annotated[Optional[float], typer.Option(help="Frame rate, where zedo lift recorded none.")] = None,
    overwrite: Annotated[bool, typer.Option(help="Replace the output if it exists.")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No progress bar or summary.")] = False,
) -> None:
    """Build a reference of typical infants for zedo analyze --norms.

    Analyses each clip as zedo analyze does and fits, per clip feature and
    age bracket, a normal distribution by maximum likelihood (Chambers et
    al. 2020). Each person track of a clip is one reference clip; at least
    10 per bracket. The reference keeps every clip's features, so that a
    clip missing a feature is compared on the features it has. Lift the
    reference's clips and the clips you compare alike (prior, preset,
    --temporal, kind of camera): the 3D features depend on it, and each
    reference clip records how it was lifted.

    Examples:

      zedo norms typical/ -o norms.json
      zedo norms a.zedo.json b.zedo.json ... --age-weeks 8 --age-weeks 14 ...
      zedo analyze infant.zedo.json --norms norms.json --age-weeks 12
    """
    if Path(output).suffix.lower() != ".json":
        raise ConfigError(f"{output}: -o/--output writes the reference as .json")
    check_writable(Path(output), overwrite)
    sources = expand_results(results)
    ages = ages_per_input(age_weeks, len(sources))
    settings = AnalysisSettings(fps=fps)
    clips = []
    with progress_bar(quiet) as bar:
        task = bar.add_task("analyse clips", total=len(sources), status="")
        for source, age in zip(sources, ages, strict=True):
            a = analyse(read_result(source), settings)
            if not a.is_sequence:
                raise ConfigError(f"{source}: no fps (neither --fps nor recorded by zedo lift --fps): a reference "
                                  "is built from clips")  # fmt: skip
            clips += features_by_person(a, age)
            bar.update(task, advance=1)
    norms = build_norms(clips, __version__)
    write_norms(output, norms, overwrite=overwrite)
    if not quiet:
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
        err_console.print(f"wrote {output}", markup=False, soft_wrap=True)
