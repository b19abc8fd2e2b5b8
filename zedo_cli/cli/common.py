"""What every command shares: the error boundary, the stderr console, output-path checks."""

from __future__ import annotations

import functools
import json
import math
import os
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any, ParamSpec, TypeVar

import typer
from rich.console import Console
from rich.table import Table
from rich.text import Text

from ..errors import ConfigError, ZedoError, one_line
from ..files import check_writable, write_text_atomic

if TYPE_CHECKING:
    from rich.progress import Progress

    from ..prior.training import TrainProgress


# Data goes to stdout; progress, logs and errors to stderr. Off a terminal (a log file, a pipe)
# lines are never wrapped at 80 columns nor padded, and tables are printed as plain lines.
# No :emoji: codes: a file name such as `a:baby:.json` is printed as it is (and rich's table of
# emoji codes is never loaded).
def _console(stderr: bool) -> Console:
    console = Console(stderr=stderr, highlight=False, emoji=False)
    console.soft_wrap = not console.is_terminal
    return console


err_console = _console(stderr=True)


def stdout_console() -> Console:
    """The console of a command's tables and notes on stdout: like stderr's, never wrapped off a terminal."""
    return _console(stderr=False)


def print_table(table: Table, console: Console | None = None) -> None:
    """A rich table on a terminal; elsewhere plain lines: the title, the header, one line per
    row, columns aligned with two spaces, nothing cut, wrapped or padded at the end."""
    console = console or err_console
    if console.is_terminal:
        console.print(table)
        return
    rows = [[_plain(c.header) for c in table.columns]]
    rows += [list(cells) for cells in zip(*([_plain(cell) for cell in c.cells] for c in table.columns), strict=True)]
    widths = [max(len(row[i]) for row in rows) for i in range(len(table.columns))]
    lines = [_plain(table.title)] if table.title else []
    for row in rows:
        lines.append("  ".join(cell.ljust(w) for cell, w in zip(row, widths, strict=True)).rstrip())
    for line in lines:
        console.print(line, markup=False, highlight=False, soft_wrap=True)


def _plain(cell: object) -> str:
    """A table cell's text without its markup or styles, on one line."""
    if isinstance(cell, Text):
        return one_line(cell.plain)
    return one_line(Text.from_markup(str(cell)).plain) if cell is not None else ""


EXIT_OK = 0
EXIT_RUNTIME = 1
EXIT_USAGE = 2
EXIT_INPUT = 3
EXIT_PARTIAL = 4  # batch: some inputs failed (the others were written)
EXIT_INTERRUPTED = 130
EXIT_BROKEN_PIPE = 141  # 128 + SIGPIPE: what a shell reports for a tool whose reader went away

# When zedo's own code began (Python's start, about 0.02 s, comes before): start-up is
# reported apart from the work, so a rate is never diluted by imports and model loading.
COMMAND_START = time.perf_counter()

P = ParamSpec("P")
R = TypeVar("R")


def output_option(help: str, panel: str | None = None) -> Any:
    """`-o/--output` of every command that writes a file (`--out`, its older spelling, is still
    read; --help shows only -o/--output)."""
    return typer.Option("--output", "-o", "--out", metavar="PATH", help=help, rich_help_panel=panel)


def internal_error(source: str, exc: Exception) -> ZedoError:
    """An unexpected exception of one input of a batch, as that input's error (exit 1); both
    engines of `zedo lift` report it so."""
    return ZedoError(f"{source}: internal error: {type(exc).__name__}: {exc}")


def error_boundary(func: Callable[P, R]) -> Callable[P, R]:
    """Turn a ZedoError into one line on stderr and its exit code; never show a traceback
    (set ZEDO_DEBUG=1 to see one for an unexpected failure)."""

    @functools.wraps(func)
    def wrapper(*args: P.args, **kwargs: P.kwargs) -> R:
        try:
            return func(*args, **kwargs)
        except ZedoError as exc:
            err_console.print(f"zedo: error: {one_line(str(exc))}", markup=False, soft_wrap=True)
            raise typer.Exit(exc.exit_code) from None
        except BrokenPipeError:  # stdout's reader stopped reading (`zedo lift x.json -o - | head -1`): quietly
            silence_stdout()
            raise typer.Exit(EXIT_BROKEN_PIPE) from None
        except KeyboardInterrupt:
            err_console.print("zedo: interrupted", markup=False, soft_wrap=True)
            raise typer.Exit(EXIT_INTERRUPTED) from None
        except typer.Exit:
            raise
        except Exception as exc:  # the last line of defence: one line, not a traceback
            if os.environ.get("ZEDO_DEBUG"):
                raise
            err_console.print(
                f"zedo: internal error: {type(exc).__name__}: {one_line(str(exc))} (set ZEDO_DEBUG=1 for a traceback)",
                markup=False,
                soft_wrap=True,
            )
            raise typer.Exit(EXIT_RUNTIME) from None

    return wrapper


def finite_or_null(value: Any) -> Any:
    """`value` with every NaN or infinite float (also numpy's) inside dicts, lists and tuples
    replaced by None, so that it serialises as strict JSON (`null`, not `NaN`)."""
    if isinstance(value, dict):
        return {k: finite_or_null(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [finite_or_null(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):  # numpy's float64 is a float
        return None
    if hasattr(value, "dtype") and getattr(value, "shape", None) == () and value.dtype.kind == "f":
        return finite_or_null(float(value))
    return value


def print_json_report(doc: dict[str, Any]) -> None:
    """A command's `--json` report on stdout: strict JSON, unknown figures (NaN: e.g. a preset
    that lifted no pose) as null."""
    sys.stdout.write(json.dumps(finite_or_null(doc), indent=1, allow_nan=False) + "\n")


STDOUT = "-"


def check_report_output(output: str | None, overwrite: bool) -> None:
    """-o/--output of a command that reports figures (evaluate, the benchmarks): a .json file
    name, or - for stdout; checked before any work."""
    if output is None or output == STDOUT:
        return
    if Path(output).suffix.lower() != ".json":
        raise ConfigError(f"{output}: -o/--output writes the figures as JSON: give a .json file name (or - for stdout)")
    check_writable(Path(output), overwrite)


def report_figures(doc: dict[str, Any], output: str | None, as_json: bool, *, overwrite: bool, quiet: bool) -> bool:
    """A command's figures as JSON: into -o's file, and on stdout with --json (or -o -).
    Returns whether stdout carried them (the human tables are then left out)."""
    if output is not None and output != STDOUT:
        text = json.dumps(finite_or_null(doc), indent=1, allow_nan=False) + "\n"
        write_text_atomic(output, text, overwrite=overwrite)
        if not quiet:
            err_console.print(f"wrote {output}", markup=False, soft_wrap=True)
    if as_json or output == STDOUT:
        print_json_report(doc)
        return True
    return False


def silence_stdout() -> None:
    """Point stdout at /dev/null, so that Python's final flush of a closed pipe stays quiet."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):  # no real file descriptor (e.g. captured by a test runner)
        pass


class LineProgress:
    """Progress for a stderr that is not a terminal (log files, CI, batch jobs): the same calls
    as rich's Progress, but one plain line per task at most every `interval` seconds."""

    def __init__(self, interval: float = 30.0) -> None:
        self.interval = interval
        self.tasks: dict[int, dict[str, Any]] = {}

    def __enter__(self) -> LineProgress:
        return self

    def __exit__(self, *exc: object) -> None:
        return None

    def add_task(self, description: str, total: float | None = 1, **fields: Any) -> int:
        now = time.monotonic()
        self.tasks[len(self.tasks)] = {"description": description, "total": total, "completed": 0,
                                       "start": now, "printed": now, **fields}  # fmt: skip
        return len(self.tasks) - 1

    def update(self, task: int, **changes: Any) -> None:
        state = self.tasks[task]
        state.update(changes)
        now = time.monotonic()
        if now - state["printed"] < self.interval:
            return
        state["printed"] = now
        status = f" {state['status']}" if state.get("status") else ""
        err_console.print(f"{state['description']}: {state['completed']}/{state['total']}{status} "
                          f"({now - state['start']:.0f} s)", markup=False, soft_wrap=True)  # fmt: skip


@contextmanager
def epoch_progress(quiet: bool, name: str, epochs: int) -> Iterator[Callable[[TrainProgress], None]]:
    """A progress display for a training run; yields the per-epoch callback to pass to it."""
    with progress_bar(quiet) as bar:
        task = bar.add_task(name, total=epochs, status="")

        def on_epoch(p: TrainProgress) -> None:
            bar.update(task, completed=p.epoch, status=f"loss {p.loss:.3f}")

        yield on_epoch


@contextmanager
def step_progress(quiet: bool, name: str) -> Iterator[Callable[[int, int], None]]:
    """A progress display for work counted in steps; yields the `on_step(done, total)` callback."""
    with progress_bar(quiet) as bar:
        task = bar.add_task(name, total=None, status="")

        def on_step(done: int, total: int) -> None:
            bar.update(task, completed=done, total=total)

        yield on_step


def progress_bar(quiet: bool) -> Progress | LineProgress:
    """A live bar on a terminal; periodic plain lines otherwise; nothing when quiet."""
    if quiet or os.environ.get("ZEDO_NO_PROGRESS"):
        return LineProgress(interval=math.inf)  # the same calls, never a line
    if not err_console.is_terminal:
        return LineProgress()
    from rich.progress import (  # only for a live bar (start-up: docs/lifting.md)
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    return Progress(
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TextColumn("{task.fields[status]}"),
        TimeElapsedColumn(),
        TimeRemainingColumn(),
        console=err_console,
        transient=False,
    )
