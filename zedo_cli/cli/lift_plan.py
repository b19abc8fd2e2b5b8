"""Which files `zedo lift` reads and writes: inputs expanded from files, folders and globs, and
one output path per input, all checked before anything is lifted."""

from __future__ import annotations

import glob
import os
from collections.abc import Callable
from pathlib import Path

from ..errors import ConfigError, InputFormatError, ZedoError
from ..files import check_can_create, check_output_folder, check_output_kind
from ..formats.readers.deeplabcut import is_deeplabcut_file
from ..formats.readers.labelme import is_labelme_folder
from ..formats.readers.openpose import is_openpose_folder, is_zedo_output
from ..formats.readers.source import check_input_file
from ..formats.writers.outputs import check_stdout, default_output_name, output_format
from ..formats.writers.result_csv import sidecar_path

STDIN = "-"
_INPUT_SUFFIXES = (".json", ".jsonl", ".ndjson")
_GLOB_CHARS = set("*?[")
PLOT_ROLES = ("first", "median", "worst")  # formats.plots writes <prefix>.<role>.png


def _folder_inputs(folder: Path) -> list[str]:
    """An OpenPose folder (per-frame `*_keypoints.json`, or numbered frames such as Pose2Sim's
    `cam01.0030.json`) or a folder of LabelMe files is one input, a sequence; any other folder
    stands for its keypoint files: JSON, JSON Lines and DeepLabCut's tables (zedo's own outputs left out)."""
    if is_openpose_folder(folder) or is_labelme_folder(folder):
        return [str(folder)]
    files = sorted(p for p in folder.iterdir()
                   if (p.suffix in _INPUT_SUFFIXES or is_deeplabcut_file(p)) and not is_zedo_output(p))  # fmt: skip
    if not files:
        raise InputFormatError(f"{folder}: folder holds no keypoint files (*.json, *.jsonl, DeepLabCut's *.csv "
                               "and *.h5) and no OpenPose frames")  # fmt: skip
    return [str(p) for p in files]


def expand_inputs(
    args: list[str],
    *,
    folder: Callable[[Path], list[str]] = _folder_inputs,
    keep: Callable[[Path], bool] = lambda p: not is_zedo_output(p),
) -> list[str]:
    """Input paths in the order given: `-` (stdin), files, folders (`folder(path)` lists what a
    folder stands for) and glob patterns the shell did not expand (quoted, or on Windows; the
    matches that `keep` accepts). Duplicates are dropped. The defaults are `zedo lift`'s."""
    out: list[str] = []
    for arg in args:
        path = Path(arg)
        if arg == STDIN:
            out.append(arg)
        elif path.is_dir():
            out += folder(path)
        elif path.exists() or path.is_symlink():  # a broken link or a loop: the reader says which
            out.append(arg)
        elif _GLOB_CHARS & set(arg):
            matches = sorted(m for m in glob.glob(arg, recursive=True) if keep(Path(m)))
            if not matches:
                raise InputFormatError(f"{arg}: no file matches this pattern")
            out += matches
        else:
            raise InputFormatError(f"{arg}: file not found")
    if out.count(STDIN) > 1:
        raise ConfigError("stdin (-) can be read only once")
    return list(dict.fromkeys(out))


def check_inputs(inputs: list[str]) -> None:
    """Every input file readable and not an image, a video, a table or an array, before any work
    (a folder's frames and stdin are checked as they are read)."""
    for name in inputs:
        if name != STDIN and not Path(name).is_dir():
            check_input_file(name)


def refused_inputs(inputs: list[str]) -> dict[str, ZedoError]:
    """`check_inputs` for a batch: the inputs that fail it, with their errors, instead of the first
    error. A batch reports a failing input and goes on with the others (exit code 4); one input's
    failure is the command's (`check_inputs`)."""
    refused: dict[str, ZedoError] = {}
    for name in inputs:
        try:
            check_inputs([name])
        except ZedoError as exc:
            refused[name] = exc
    return refused


def check_output_options(out: str | None, output_dir: Path | None, fmt: str | None) -> None:
    """The usage errors of -o / --output-dir / --output-format, before the inputs are looked at."""
    if out is not None and output_dir is not None:
        raise ConfigError("give -o/--output or --output-dir, not both")
    if out is not None:
        if out != STDIN:
            check_output_kind(Path(out))  # -o /dev/null, -o some_folder/: said as such
        output_format(out, fmt)  # a contradicting or missing extension fails here


def plan_outputs(
    inputs: list[str], out: str | None, output_dir: Path | None, fmt: str | None, overwrite: bool
) -> list[str]:
    """The output of each input, or `-` for stdout. Refuses, before any work, clashing
    outputs, existing files without `overwrite` and missing folders."""
    if out is not None and len(inputs) > 1:
        raise ConfigError(
            "-o/--output names one output; for several inputs use --output-dir (or none: beside each input)"
        )
    if out is not None and output_dir is not None:
        raise ConfigError("give -o/--output or --output-dir, not both")
    if out is not None:
        output_format(out, fmt)  # a contradicting extension fails here
        outputs = [out]
    else:
        outputs = []
        for name in inputs:
            if name == STDIN:
                if output_dir is None:
                    outputs.append(STDIN)  # a pipeline: stdin to stdout
                    continue
                name = "stdin"
            default = default_output_name(Path(name.rstrip("/")), fmt or "json")
            outputs.append(str(output_dir / default.name if output_dir is not None else default))
    for dst in outputs:  # NPZ, TRC and C3D are files only: refused before any work
        check_stdout(dst, output_format(dst, fmt))
    _check_inputs_kept(inputs, outputs, fmt)  # first: --overwrite would not help
    _check_outputs(inputs, outputs, overwrite)
    return outputs


def _input_files(inputs: list[str]) -> list[Path]:
    """Every file the inputs read: the files given, and the files inside a folder input."""
    files: list[Path] = []
    for name in inputs:
        if name == STDIN:
            continue
        path = Path(name)
        files += sorted(p for p in path.iterdir() if p.is_file()) if path.is_dir() else [path]
    return files


def _same_file(a: Path, b: Path) -> bool:
    """The same file: the same real path, or (both existing) the same inode (a hard link)."""
    if os.path.realpath(a) == os.path.realpath(b):  # never raises: a symlink loop is the reader's to report
        return True
    try:
        return a.exists() and b.exists() and os.path.samefile(a, b)
    except OSError:
        return False


def _written_files(outputs: list[str], fmt: str | None) -> list[Path]:
    """The files the outputs create: each output, and a CSV output's `.meta.json` sidecar."""
    written = []
    for out in outputs:
        if out != STDIN:
            written.append(Path(out))
            if output_format(out, fmt) == "csv":
                written.append(sidecar_path(out))
    return written


def _check_inputs_kept(inputs: list[str], outputs: list[str], fmt: str | None) -> None:
    """No output (or sidecar) may replace an input of the batch, even with --overwrite: the
    input would be lost, and a later input of the batch would read a result instead."""
    files = _input_files(inputs)
    for written in _written_files(outputs, fmt):
        for src in files:
            if _same_file(written, src):
                raise ConfigError(f"{written}: is an input of this run ({src}); it is never overwritten, "
                                  "not even with --overwrite: choose another -o or --output-dir")  # fmt: skip


def _refuse_existing(existing: list[str]) -> None:
    """The one usage error for outputs that exist (without --overwrite): the first three named, the rest counted."""
    if existing:
        more = f" and {len(existing) - 3} more" if len(existing) > 3 else ""
        verb = "already exists" if len(existing) == 1 else "already exist"
        raise ConfigError(f"{', '.join(existing[:3])}{more}: {verb}; pass --overwrite to replace")


def output_stem(source: str) -> str:
    """`clip` for a result `clip.zedo.json` (else the file's stem; `stdin` for -): the stem of
    the files made from a result (analyze, export)."""
    if source == STDIN:
        return "stdin"
    name = Path(source).name
    return name.split(".zedo.")[0] if ".zedo." in name else Path(source).stem


def plot_prefix(output: str) -> str:
    """The plots' file-name prefix for an output: its name before `.zedo.` (`stdin` for stdout)."""
    return "stdin" if output == STDIN else Path(output).name.split(".zedo.")[0]


def check_plot_paths(inputs: list[str], outputs: list[str], plot_dir: Path, overwrite: bool) -> None:
    """Every PNG `--plot DIR` may write, checked before any work: the folder is a folder (or
    can be made), no two inputs share a plot name, and no plot replaces an input, or an
    existing file without `overwrite`."""
    if plot_dir.exists() and not plot_dir.is_dir():
        raise ConfigError(f"--plot {plot_dir}: exists and is not a folder")
    owner: dict[str, str] = {}
    existing = []
    files = _input_files(inputs)
    for src, out in zip(inputs, outputs, strict=True):
        for role in PLOT_ROLES:
            png = plot_dir / f"{plot_prefix(out)}.{role}.png"
            key = os.path.realpath(png)
            if key in owner:
                raise ConfigError(f"{owner[key]} and {src} would both be plotted to {png}; use separate --plot folders")
            owner[key] = src
            if any(_same_file(png, f) for f in files):
                raise ConfigError(f"{png}: is an input of this run; plots never overwrite an input")
            if check_output_kind(png) and not overwrite:
                existing.append(str(png))
    _refuse_existing(existing)


def _check_outputs(inputs: list[str], outputs: list[str], overwrite: bool) -> None:
    seen: dict[str, str] = {}
    existing = []
    for src, dst in zip(inputs, outputs, strict=True):
        if dst == STDIN:
            continue
        key = os.path.realpath(dst)
        if key in seen:
            raise ConfigError(f"{seen[key]} and {src} would both be written to {dst}; use separate --output-dir runs")
        seen[key] = src
        check_output_folder(Path(dst).parent)
        if check_output_kind(Path(dst)) and not overwrite:
            existing.append(dst)
    for dst in {str(Path(d).parent): d for d in reversed(outputs) if d != STDIN}.values():
        check_can_create(Path(dst))  # a read-only folder fails here (naming its first output), before any work
    _refuse_existing(existing)
