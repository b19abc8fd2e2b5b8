"""What every command shares: the error boundary, the stderr console, output-path checks."""

from __future__ import annotations

import functools
import os
from collections.abc import Callable
from typing import ParamSpec, TypeVar

import typer
from rich.console import Console
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    TextColumn,
    TimeElapsedColumn,
    TimeRemainingColumn,
)

from ..errors import ZedoError

# Data goes to stdout; progress, logs and errors to stderr.
err_console = Console(stderr=True, highlight=False)

EXIT_OK = 0
EXIT_RUNTIME = 1
EXIT_USAGE = 2
EXIT_INPUT = 3
EXIT_PARTIAL = 4  # batch: some inputs lifted, some failed
EXIT_INTERRUPTED = 130

P = ParamSpec("P")
R = TypeVar("R")


def error_boundary(func: Callable[P, R]) -> Callable[P, R]:
    """Turn a ZedoError into one line on stderr and its exit code; never show a traceback
    (set ZEDO_DEBUG=1 to see one for an unexpected failure)."""

    @functools.wraps(func)
    def wrapper(*args: P.args, **kwargs: P.kwargs) -> R:
        try:
            return func(*args, **kwargs)
        except ZedoError as exc:
            err_console.print(f"zedo: error: {exc}", markup=False, soft_wrap=True)
            raise typer.Exit(exc.exit_code) from None
        except KeyboardInterrupt:
            err_console.print("zedo: interrupted", markup=False, soft_wrap=True)
            raise typer.Exit(EXIT_INTERRUPTED) from None
        except typer.Exit:
            raise
        except Exception as exc:  # the last line of defence: one line, not a traceback
            if os.environ.get("ZEDO_DEBUG"):
                raise
            err_console.print(
                f"zedo: internal error: {type(exc).__name__}: {exc} (set ZEDO_DEBUG=1 for a traceback)",
                markup=False,
                soft_wrap=True,
            )
            raise typer.Exit(EXIT_RUNTIME) from None

    return wrapper


def progress_bar(quiet: bool) -> Progress:
    return Progress(
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TextColumn("{task.fields[status]}"),
        TimeElapsedColumn(),
        TimeRemainingColumn(),
        console=err_console,
        disable=quiet or bool(os.environ.get("ZEDO_NO_PROGRESS")),
        transient=False,
    )
